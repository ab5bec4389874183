#include "interchange/glb_export.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <tiny_gltf.h>

namespace penumbra::interchange {

namespace {

// One primitive's worth of vertex data before it goes into the buffer.
struct PrimitiveData {
  std::vector<float> positions;  // xyz
  std::vector<float> colors;     // rgb
  std::vector<uint32_t> indices;
  void add(const Vec3& p, const Vec3& color) {
    positions.insert(positions.end(), {float(p.x), float(p.y), float(p.z)});
    colors.insert(colors.end(), {float(color.x), float(color.y), float(color.z)});
  }
  size_t vertexCount() const { return positions.size() / 3; }
};

class GltfBuilder {
 public:
  GltfBuilder() {
    model_.asset.version = "2.0";
    model_.asset.generator = "penumbra";
    model_.buffers.emplace_back();
    model_.scenes.emplace_back();
    model_.defaultScene = 0;
  }

  int unlitMaterial(const std::string& name, const Vec3& color) {
    tinygltf::Material material;
    material.name = name;
    material.pbrMetallicRoughness.baseColorFactor = {color.x, color.y, color.z, 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
    if (model_.extensionsUsed.empty()) model_.extensionsUsed.push_back("KHR_materials_unlit");
    model_.materials.push_back(material);
    return int(model_.materials.size() - 1);
  }

  // A mesh of one primitive and a node that shows it (world space: no transform).
  void addMesh(const std::string& name, const PrimitiveData& data, int material, int mode) {
    tinygltf::Primitive primitive;
    primitive.mode = mode;
    primitive.material = material;
    primitive.attributes["POSITION"] = accessor(data.positions, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    if (!data.colors.empty())
      primitive.attributes["COLOR_0"] = accessor(data.colors, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    primitive.indices = accessor(data.indices, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER, false);
    tinygltf::Mesh mesh;
    mesh.name = name;
    mesh.primitives.push_back(primitive);
    model_.meshes.push_back(mesh);
    tinygltf::Node node;
    node.name = name;
    node.mesh = int(model_.meshes.size() - 1);
    model_.nodes.push_back(node);
    model_.scenes[0].nodes.push_back(int(model_.nodes.size() - 1));
  }

  void setExtras(tinygltf::Value::Object extras) {
    model_.asset.extras = tinygltf::Value(tinygltf::Value::Object{{"penumbra", tinygltf::Value(std::move(extras))}});
  }

  std::vector<uint8_t> glb() {
    tinygltf::TinyGLTF writer;
    std::ostringstream out;
    if (!writer.WriteGltfSceneToStream(&model_, out, false, true))
      throw std::runtime_error("tinygltf could not write the GLB");
    const std::string bytes = out.str();
    return std::vector<uint8_t>(bytes.begin(), bytes.end());
  }

 private:
  template <typename T>
  int accessor(const std::vector<T>& values, int type, int target, bool withBounds) {
    std::vector<unsigned char>& data = model_.buffers[0].data;
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = data.size();
    view.byteLength = values.size() * sizeof(T);
    view.target = target;
    data.resize(data.size() + view.byteLength);
    std::memcpy(data.data() + view.byteOffset, values.data(), view.byteLength);
    model_.bufferViews.push_back(view);

    tinygltf::Accessor accessor;
    accessor.bufferView = int(model_.bufferViews.size() - 1);
    accessor.componentType = std::is_same_v<T, float> ? TINYGLTF_COMPONENT_TYPE_FLOAT : TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    accessor.type = type;
    const size_t components = type == TINYGLTF_TYPE_VEC3 ? 3 : 1;
    accessor.count = values.size() / components;
    if (withBounds) {  // POSITION must carry min and max
      accessor.minValues.assign(components, INFINITY);
      accessor.maxValues.assign(components, -INFINITY);
      for (size_t i = 0; i < values.size(); ++i) {
        accessor.minValues[i % components] = std::min(accessor.minValues[i % components], double(values[i]));
        accessor.maxValues[i % components] = std::max(accessor.maxValues[i % components], double(values[i]));
      }
    }
    model_.accessors.push_back(accessor);
    return int(model_.accessors.size() - 1);
  }

  tinygltf::Model model_;
};

// indirect: the same receiver's indirect irradiance (GlbOptions::indirect), or null.
Vec3 radianceOf(const Scene& scene, const ReceiverMesh& receiver, const ReceiverMesh* indirect, size_t vertex) {
  const Vec3 e = receiver.irradiance[vertex] + (indirect ? indirect->irradiance.at(vertex) : Vec3(0.0));
  return scene.albedo(receiver.face) / M_PI * e;
}

}  // namespace

GlbFile meshToGlb(const Scene& scene, const Mesh& mesh, const GlbOptions& options) {
  if (options.indirect && options.indirect->receivers.size() != mesh.receivers.size())
    throw std::invalid_argument("GLB: the indirect mesh is not of the lit mesh's shape");
  auto indirectOf = [&](const ReceiverMesh& receiver) {
    return options.indirect ? &options.indirect->receivers[size_t(&receiver - mesh.receivers.data())] : nullptr;
  };
  GlbFile file;
  file.colorScale = options.colorScale;
  if (!(file.colorScale > 0)) {
    double brightest = 0;
    for (const ReceiverMesh& receiver : mesh.receivers)
      for (size_t v = 0; v < receiver.positions.size(); ++v) {
        const Vec3 radiance = radianceOf(scene, receiver, indirectOf(receiver), v);
        brightest = std::max({brightest, radiance.x, radiance.y, radiance.z});
      }
    file.colorScale = brightest > 0 ? 1 / brightest : 1;
  }

  GltfBuilder builder;
  const int unlit = builder.unlitMaterial("penumbra-lit-mesh", Vec3(1.0));
  std::map<uint32_t, std::vector<const ReceiverMesh*>> receiversOf;
  std::map<FaceId, bool> received;
  for (const ReceiverMesh& receiver : mesh.receivers) {
    receiversOf[receiver.face.object].push_back(&receiver);
    received[receiver.face] = true;
  }
  std::map<uint32_t, std::vector<const Face*>> darkFacesOf;
  for (const Face& face : scene.faces())
    if (!received.count(face.id)) darkFacesOf[face.id.object].push_back(&face);

  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const uint32_t handle = scene.handleOf(i);
    PrimitiveData data;
    for (const ReceiverMesh* receiver : receiversOf[handle]) {
      const uint32_t first = uint32_t(data.vertexCount());
      for (size_t v = 0; v < receiver->positions.size(); ++v)
        data.add(receiver->positions[v], radianceOf(scene, *receiver, indirectOf(*receiver), v) * file.colorScale);
      for (const auto& t : receiver->triangles) data.indices.insert(data.indices.end(), {first + t[0], first + t[1], first + t[2]});
    }
    for (const Face* face : darkFacesOf[handle]) {  // lit by nothing: black, as a fan (faces are convex)
      const uint32_t first = uint32_t(data.vertexCount());
      for (const Vec3& p : face->polygon) data.add(p, Vec3(0.0));
      for (uint32_t k = 1; k + 1 < face->polygon.size(); ++k) data.indices.insert(data.indices.end(), {first, first + k, first + k + 1});
    }
    if (data.indices.empty()) continue;
    file.vertices += data.vertexCount();
    file.triangles += data.indices.size() / 3;
    builder.addMesh(scene.objects()[i].id, data, unlit, TINYGLTF_MODE_TRIANGLES);
    ++file.meshes;
  }
  if (options.lights && !scene.lights().empty()) {
    PrimitiveData data;
    for (const Light& light : scene.lights()) {
      const uint32_t first = uint32_t(data.vertexCount());
      for (const Vec3& p : light.polygon) data.add(p, light.radiance * file.colorScale);
      for (uint32_t k = 1; k + 1 < light.polygon.size(); ++k) data.indices.insert(data.indices.end(), {first, first + k, first + k + 1});
    }
    builder.addMesh("lights", data, unlit, TINYGLTF_MODE_TRIANGLES);
    ++file.meshes;
  }
  if (!options.edges.empty()) {
    PrimitiveData data;
    for (const Segment3& edge : options.edges) {
      for (const Vec3& p : edge) {
        data.positions.insert(data.positions.end(), {float(p.x), float(p.y), float(p.z)});
        data.indices.push_back(uint32_t(data.indices.size()));
      }
    }
    builder.addMesh("discontinuities", data, builder.unlitMaterial("penumbra-discontinuities", Vec3(1, 0.35, 0)),
                    TINYGLTF_MODE_LINE);
    ++file.meshes;
  }
  builder.setExtras({{"color_scale", tinygltf::Value(file.colorScale)},
                     {"indirect", tinygltf::Value(options.indirect != nullptr)},
                     {"color", tinygltf::Value(std::string("COLOR_0 = linear radiance (W m^-2 sr^-1) x color_scale"))}});
  file.bytes = builder.glb();
  return file;
}

GlbFile saveMeshGlb(const Scene& scene, const Mesh& mesh, const std::string& path, const GlbOptions& options) {
  GlbFile file = meshToGlb(scene, mesh, options);
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(file.bytes.data()), std::streamsize(file.bytes.size()));
  if (!out) throw std::runtime_error("cannot write " + path);
  return file;
}

}  // namespace penumbra::interchange
