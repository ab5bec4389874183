#include "interchange/glb_export.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "core/illum/ambient_fill.h"
#include "core/raycast/camera_projection.h"
#include "interchange/penumbra_extras.h"
#include "protocol/camera_json.h"
#include "protocol/material_json.h"

namespace penumbra::interchange {

namespace {

void append(std::vector<float>& out, const Vec3& v) { out.insert(out.end(), {float(v.x), float(v.y), float(v.z)}); }

// One primitive's worth of vertex data before it goes into the buffer: positions, and for an
// object's faces the display colour, the exact values and the scene face (empty otherwise).
struct PrimitiveData {
  std::vector<float> positions, colors, radiance, irradiance;  // xyz / rgb
  std::vector<float> faces;  // the vertex's face index within its object (exact up to 2^24)
  std::vector<uint32_t> indices;
  void add(const Vec3& p) { append(positions, p); }
  void add(const Vec3& p, const Vec3& color, const Vec3& exactRadiance, const Vec3& exactIrradiance, uint32_t face) {
    append(positions, p);
    append(colors, color);
    append(radiance, exactRadiance);
    append(irradiance, exactIrradiance);
    faces.push_back(float(face));
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

  // `extras`: what the importer reads back (penumbra_extras.h); null for none.
  int unlitMaterial(const std::string& name, const Vec3& color, const nlohmann::json& extras = nullptr) {
    tinygltf::Material material;
    material.name = name;
    if (!extras.is_null()) material.extras = toGltfValue({{kPenumbraExtras, extras}});
    material.pbrMetallicRoughness.baseColorFactor = {color.x, color.y, color.z, 1.0};
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    material.extensions["KHR_materials_unlit"] = tinygltf::Value(tinygltf::Value::Object{});
    use("KHR_materials_unlit");
    model_.materials.push_back(material);
    return int(model_.materials.size() - 1);
  }

  // A black surface that emits `emitted` (linear, any size): emissiveFactor in [0, 1] and the
  // rest as KHR_materials_emissive_strength.
  int emissiveMaterial(const std::string& name, const Vec3& emitted, const nlohmann::json& extras) {
    tinygltf::Material material;
    material.name = name;
    material.extras = toGltfValue({{kPenumbraExtras, extras}});
    material.pbrMetallicRoughness.baseColorFactor = {0, 0, 0, 1};
    material.pbrMetallicRoughness.metallicFactor = 0;
    material.pbrMetallicRoughness.roughnessFactor = 1;
    const double strength = std::max({emitted.x, emitted.y, emitted.z});
    const Vec3 factor = strength > 0 ? emitted / strength : Vec3(0.0);
    material.emissiveFactor = {factor.x, factor.y, factor.z};
    if (strength != 1 && strength > 0) {
      material.extensions["KHR_materials_emissive_strength"] =
          tinygltf::Value(tinygltf::Value::Object{{"emissiveStrength", tinygltf::Value(strength)}});
      use("KHR_materials_emissive_strength");
    }
    model_.materials.push_back(material);
    return int(model_.materials.size() - 1);
  }

  // A camera node at `camera` (glTF cameras look down their −Z with +Y up). No aspect ratio:
  // the viewer's (an orthographic view is square: xmag = ymag).
  // `extras`: the scene's own camera for the importer (penumbra_extras.h); null for none.
  void addCamera(const Camera& camera, const nlohmann::json& extras) {
    tinygltf::Camera out;
    out.name = "camera";
    if (camera.projection == Camera::Projection::Orthographic) {
      out.type = "orthographic";
      out.orthographic.ymag = camera.height / 2;
      out.orthographic.xmag = camera.height / 2;
      out.orthographic.znear = camera.near;
      out.orthographic.zfar = camera.far;
    } else {
      out.type = "perspective";
      out.perspective.yfov = camera.fovYDeg * M_PI / 180;
      out.perspective.znear = camera.near;
      out.perspective.zfar = camera.far;
    }
    model_.cameras.push_back(out);
    const Vec3 back = glm::normalize(camera.position - camera.target);
    const Vec3 right = glm::normalize(glm::cross(camera.up, back));
    const glm::dquat rotation = glm::quat_cast(glm::dmat3(right, glm::cross(back, right), back));
    tinygltf::Node node;
    node.name = "camera";
    node.camera = int(model_.cameras.size() - 1);
    if (!extras.is_null()) node.extras = toGltfValue({{kPenumbraExtras, extras}});
    node.translation = {camera.position.x, camera.position.y, camera.position.z};
    node.rotation = {rotation.x, rotation.y, rotation.z, rotation.w};
    model_.nodes.push_back(node);
    model_.scenes[0].nodes.push_back(int(model_.nodes.size() - 1));
  }

  // A mesh of one primitive and a node that shows it (world space: no transform).
  void addMesh(const std::string& name, const PrimitiveData& data, int material, int mode) {
    tinygltf::Primitive primitive;
    primitive.mode = mode;
    primitive.material = material;
    primitive.attributes["POSITION"] = accessor(data.positions, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, true);
    if (!data.colors.empty()) {
      primitive.attributes["COLOR_0"] = accessor(data.colors, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      primitive.attributes["_RADIANCE"] = accessor(data.radiance, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      primitive.attributes["_IRRADIANCE"] =
          accessor(data.irradiance, TINYGLTF_TYPE_VEC3, TINYGLTF_TARGET_ARRAY_BUFFER, false);
      primitive.attributes[kFaceAttribute] = accessor(data.faces, TINYGLTF_TYPE_SCALAR, TINYGLTF_TARGET_ARRAY_BUFFER, false);
    }
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
  void use(const std::string& extension) {
    if (std::find(model_.extensionsUsed.begin(), model_.extensionsUsed.end(), extension) == model_.extensionsUsed.end())
      model_.extensionsUsed.push_back(extension);
  }

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

// A receiver vertex's exact outgoing radiance, albedo/π · (E + E_indirect) (indirect: the same
// receiver's indirect irradiance, GlbOptions::indirect, or null), and its display radiance with
// the fill: the indirect irradiance when given, else `ambient`.
Vec3 exactRadiance(const Scene& scene, const ReceiverMesh& receiver, const ReceiverMesh* indirect, size_t vertex) {
  const Vec3 e = receiver.irradiance[vertex] + (indirect ? indirect->irradiance.at(vertex) : Vec3(0.0));
  return scene.albedo(receiver.face) / M_PI * e;
}
Vec3 displayRadiance(const Scene& scene, const ReceiverMesh& receiver, const ReceiverMesh* indirect, size_t vertex,
                     const Vec3& ambient) {
  return exactRadiance(scene, receiver, indirect, vertex) +
         (indirect ? Vec3(0.0) : scene.albedo(receiver.face) / M_PI * ambient);
}

// The page's automatic exposure (web_client/src/tone_map.js): 1 / the 99th percentile of the
// display radiance's largest channel over the receivers' vertices; 1 when all are dark.
double automaticScale(const std::vector<double>& largestChannels) {
  std::vector<double> values = largestChannels;
  if (values.empty()) return 1;
  const size_t at = std::min(values.size() - 1, size_t(std::floor(0.99 * double(values.size()))));
  std::nth_element(values.begin(), values.begin() + long(at), values.end());
  return values[at] > 0 ? 1 / values[at] : 1;
}

Vec3 clampedColour(const Vec3& radiance, double scale) { return glm::min(radiance * scale, Vec3(1.0)); }

}  // namespace

GlbFile meshToGlb(const Scene& scene, const Mesh& mesh, const GlbOptions& options) {
  if (options.indirect && options.indirect->receivers.size() != mesh.receivers.size())
    throw std::invalid_argument("GLB: the indirect mesh is not of the lit mesh's shape");
  auto indirectOf = [&](const ReceiverMesh& receiver) {
    return options.indirect ? &options.indirect->receivers[size_t(&receiver - mesh.receivers.data())] : nullptr;
  };
  GlbFile file;
  file.ambient = ambientIrradiance(scene);
  file.colorScale = options.colorScale;
  if (!(file.colorScale > 0)) {
    std::vector<double> largest;
    for (const ReceiverMesh& receiver : mesh.receivers)
      for (size_t v = 0; v < receiver.positions.size(); ++v) {
        const Vec3 radiance = displayRadiance(scene, receiver, indirectOf(receiver), v, file.ambient);
        largest.push_back(std::max({radiance.x, radiance.y, radiance.z}));
      }
    file.colorScale = automaticScale(largest);
  }

  GltfBuilder builder;
  // Every object shows its COLOR_0 through a white unlit material; each scene material has its
  // own, carrying the material for the importer (the scene's default: "penumbra-lit-mesh").
  int unlit = -1;
  std::map<size_t, int> glbMaterialOf;  // scene material index → glTF material
  auto materialOf = [&](const Object& object) {
    const std::optional<size_t> m = scene.findMaterial(object.material);
    if (!m && unlit < 0) unlit = builder.unlitMaterial("penumbra-lit-mesh", Vec3(1.0), {{"default_material", true}});
    if (!m) return unlit;
    if (!glbMaterialOf.count(*m)) {
      const Material& material = scene.materials()[*m];
      glbMaterialOf[*m] = builder.unlitMaterial(material.id, Vec3(1.0), {{"material", protocol::materialToJson(material)}});
    }
    return glbMaterialOf[*m];
  };
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
      const ReceiverMesh* indirect = indirectOf(*receiver);
      for (size_t v = 0; v < receiver->positions.size(); ++v)
        data.add(receiver->positions[v],
                 clampedColour(displayRadiance(scene, *receiver, indirect, v, file.ambient), file.colorScale),
                 exactRadiance(scene, *receiver, indirect, v), receiver->irradiance[v], receiver->face.face);
      for (const auto& t : receiver->triangles) data.indices.insert(data.indices.end(), {first + t[0], first + t[1], first + t[2]});
    }
    for (const Face* face : darkFacesOf[handle]) {  // lit by no light: the fill only, as a fan (faces are convex)
      const uint32_t first = uint32_t(data.vertexCount());
      const Vec3 fill = options.indirect ? Vec3(0.0) : scene.albedo(face->id) / M_PI * file.ambient;
      for (const Vec3& p : face->polygon)
        data.add(p, clampedColour(fill, file.colorScale), Vec3(0.0), Vec3(0.0), face->id.face);
      for (uint32_t k = 1; k + 1 < face->polygon.size(); ++k) data.indices.insert(data.indices.end(), {first, first + k, first + k + 1});
    }
    if (data.indices.empty()) continue;
    file.vertices += data.vertexCount();
    file.triangles += data.indices.size() / 3;
    builder.addMesh(scene.objects()[i].id, data, materialOf(scene.objects()[i]), TINYGLTF_MODE_TRIANGLES);
    ++file.meshes;
  }
  if (options.lights)
    for (const Light& light : scene.lights()) {
      PrimitiveData data;
      for (const Vec3& p : light.polygon) data.add(p);
      for (uint32_t k = 1; k + 1 < light.polygon.size(); ++k) data.indices.insert(data.indices.end(), {0, k, k + 1});
      const nlohmann::json radiance = {{"radiance", {light.radiance.x, light.radiance.y, light.radiance.z}}};
      builder.addMesh(light.id, data, builder.emissiveMaterial("light " + light.id, light.radiance * file.colorScale, radiance),
                      TINYGLTF_MODE_TRIANGLES);
      ++file.meshes;
    }
  if (!options.edges.empty()) {
    PrimitiveData data;
    for (const Segment3& edge : options.edges)
      for (const Vec3& p : edge) {
        data.add(p);
        data.indices.push_back(uint32_t(data.indices.size()));
      }
    builder.addMesh("discontinuities", data, builder.unlitMaterial("penumbra-discontinuities", Vec3(1, 0.35, 0)),
                    TINYGLTF_MODE_LINE);
    ++file.meshes;
  }
  builder.addCamera(scene.camera() ? *scene.camera() : defaultCamera(scene.bounds()),
                    scene.camera() ? nlohmann::json{{"camera", protocol::cameraToJson(*scene.camera())}} : nullptr);
  auto rgb = [](const Vec3& v) {
    return tinygltf::Value(tinygltf::Value::Array{tinygltf::Value(v.x), tinygltf::Value(v.y), tinygltf::Value(v.z)});
  };
  builder.setExtras(
      {{"color_scale", tinygltf::Value(file.colorScale)},
       {"ambient", rgb(file.ambient)},
       {"indirect", tinygltf::Value(options.indirect != nullptr)},
       {"color", tinygltf::Value(std::string("COLOR_0 = min(1, color_scale x albedo/pi x (E + fill)), fill = the "
                                             "indirect irradiance if indirect, else ambient (W m^-2)"))},
       {"radiance", tinygltf::Value(std::string("_RADIANCE = albedo/pi x (E + indirect) (W m^-2 sr^-1)"))},
       {"irradiance", tinygltf::Value(std::string("_IRRADIANCE = E, the exact direct irradiance (W m^-2)"))},
       {"faces", tinygltf::Value(std::string("_FACE = the vertex's face index within its object (node name = object "
                                             "id); materials' extras.penumbra = the scene's material"))}});
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
