#include "interchange/gltf_import.h"

#include "interchange/face_outline.h"
#include "interchange/gltf_extensions.h"
#include "interchange/gltf_meshopt.h"
#include "interchange/material_mapping.h"
#include "interchange/penumbra_extras.h"
#include "interchange/texture_average.h"

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <tiny_gltf.h>

#include "protocol/material_json.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {

namespace {

using protocol::ValidationError;

constexpr size_t kMaxGltfBytes = size_t(256) << 20;
constexpr int kMaxNodeDepth = 64;

// Images are decoded (base colour textures are averaged into albedos: texture_average.h) only
// when their header gives a PNG or JPEG size within what is left of kMaxTexturePixels; any other
// is left empty (its textures ignored, counted) rather than failing the file.
bool loadImageWithinBudget(tinygltf::Image* image, const int index, std::string* /*err*/, std::string* warn, int width,
                           int height, const unsigned char* bytes, int size, void* pixelsLeft) {
  size_t& left = *static_cast<size_t*>(pixelsLeft);
  const auto dimensions = encodedImageSize(bytes, size_t(std::max(size, 0)));
  if (!dimensions || dimensions->first <= 0 || dimensions->second <= 0 ||
      size_t(dimensions->first) * size_t(dimensions->second) > left)
    return true;
  left -= size_t(dimensions->first) * size_t(dimensions->second);
  std::string decodeError;
  if (!tinygltf::LoadImageData(image, index, &decodeError, warn, width, height, bytes, size, nullptr)) image->image.clear();
  return true;
}

// Uploads must not reach the server's files through buffer URIs.
bool noFile(const std::string&, void*) { return false; }
std::string samePath(const std::string& path, void*) { return path; }
bool noRead(std::vector<unsigned char>*, std::string* err, const std::string& path, void*) {
  if (err) *err += "external buffer '" + path + "' is not allowed here (embed it: GLB or a data: URI)\n";
  return false;
}
bool noWrite(std::string*, const std::string&, const std::vector<unsigned char>&, void*) { return false; }

bool isBinary(const std::vector<uint8_t>& bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
}

std::string at(const std::string& list, size_t index) { return list + "[" + std::to_string(index) + "]"; }

// The bytes of element i of an accessor, checked against its view and buffer.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, int index, const std::string& path) : path_(path) {
    if (index < 0 || size_t(index) >= model.accessors.size()) throw ValidationError(path, "no such accessor");
    const tinygltf::Accessor& accessor = model.accessors[size_t(index)];
    if (accessor.sparse.isSparse) throw ValidationError(path, "sparse accessors are not supported");
    if (accessor.bufferView < 0 || size_t(accessor.bufferView) >= model.bufferViews.size())
      throw ValidationError(path, "accessor has no buffer view");
    const tinygltf::BufferView& view = model.bufferViews[size_t(accessor.bufferView)];
    if (view.buffer < 0 || size_t(view.buffer) >= model.buffers.size())
      throw ValidationError(path, "buffer view has no buffer");
    const std::vector<unsigned char>& data = model.buffers[size_t(view.buffer)].data;
    componentType_ = accessor.componentType;
    normalized_ = accessor.normalized;
    components_ = tinygltf::GetNumComponentsInType(uint32_t(accessor.type));
    const int componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(componentType_));
    if (components_ <= 0 || componentSize <= 0) throw ValidationError(path, "unknown accessor type");
    elementSize_ = size_t(components_) * size_t(componentSize);
    stride_ = view.byteStride ? view.byteStride : elementSize_;
    count_ = accessor.count;
    if (view.byteOffset + view.byteLength > data.size())
      throw ValidationError(path, "buffer view runs past its buffer");
    if (count_ && accessor.byteOffset + stride_ * (count_ - 1) + elementSize_ > view.byteLength)
      throw ValidationError(path, "accessor runs past its buffer view");
    base_ = data.data() + view.byteOffset + accessor.byteOffset;
  }

  size_t count() const { return count_; }
  int components() const { return components_; }
  int componentType() const { return componentType_; }

  // Integer components as stored, or mapped to [0, 1] / [−1, 1] when the accessor is
  // normalized (KHR_mesh_quantization stores positions as (normalized) bytes and shorts).
  double component(size_t i, int c) const {
    const unsigned char* p = base_ + stride_ * i + size_t(c) * (elementSize_ / size_t(components_));
    auto scaled = [&](double v, double max, bool isSigned) {
      return !normalized_ ? v : isSigned ? std::max(v / max, -1.0) : v / max;
    };
    switch (componentType_) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
      case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double v; std::memcpy(&v, p, 8); return v; }
      case TINYGLTF_COMPONENT_TYPE_BYTE: { int8_t v; std::memcpy(&v, p, 1); return scaled(v, 127, true); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return scaled(*p, 255, false);
      case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; std::memcpy(&v, p, 2); return scaled(v, 32767, true); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return scaled(v, 65535, false); }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return v; }
      default: throw ValidationError(path_, "unsupported component type " + std::to_string(componentType_));
    }
  }

 private:
  std::string path_;
  const unsigned char* base_ = nullptr;
  size_t stride_ = 0, elementSize_ = 0, count_ = 0;
  int components_ = 0, componentType_ = 0;
  bool normalized_ = false;
};

Mat4 localMatrix(const tinygltf::Node& node) {
  if (node.matrix.size() == 16) {
    Mat4 m;
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) m[c][r] = node.matrix[size_t(c * 4 + r)];  // column-major, like GLM
    return m;
  }
  Mat4 m(1.0);
  if (node.translation.size() == 3) m = glm::translate(m, Vec3(node.translation[0], node.translation[1], node.translation[2]));
  if (node.rotation.size() == 4)
    m = m * glm::mat4_cast(glm::dquat(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]));
  if (node.scale.size() == 3) m = glm::scale(m, Vec3(node.scale[0], node.scale[1], node.scale[2]));
  return m;
}

// A number from a material extension's object, or fallback.
double extensionNumber(const tinygltf::Material& m, const char* extension, const char* key, double fallback) {
  const auto ext = m.extensions.find(extension);
  if (ext == m.extensions.end() || !ext->second.Has(key)) return fallback;
  return ext->second.Get(key).GetNumberAsDouble();
}

// Metallic (>= 0.5; glTF's default is 1) -> conductor with base colour as F0; KHR_materials_transmission (>= 0.5) ->
// dielectric with KHR_materials_ior (default 1.5); roughness alpha = roughnessFactor².
void mapMicrofacet(const tinygltf::Material& m, ImportedMaterial& material, ImportReport& report) {
  if (m.extensions.count("KHR_materials_unlit")) return;  // e.g. Penumbra's own lit-mesh export
  const auto& pbr = m.pbrMetallicRoughness;
  const double alpha = alphaFromPerceptual(pbr.roughnessFactor);
  if (pbr.metallicRoughnessTexture.index >= 0) report.count("textures_ignored");  // roughness: the factor only
  if (extensionNumber(m, "KHR_materials_transmission", "transmissionFactor", 0) >= 0.5) {
    material.surface.type = MaterialType::Dielectric;
    material.surface.roughness = Vec2(alpha);
    const double ior = extensionNumber(m, "KHR_materials_ior", "ior", 1.5);
    material.surface.ior = ior > 1 && ior <= 4 ? ior : 1.5;
    report.count("materials_mapped_to_dielectric");
  } else if (pbr.metallicFactor >= 0.5) {
    setConductorFromBaseColor(material.surface, material.albedo);
    material.surface.roughness = Vec2(alpha);
    report.count("materials_mapped_to_conductor");
  }
}

// Penumbra's own export (penumbra_extras.h): the scene's material, or a light's exact radiance
// (its emissive factor is scaled by the export's exposure). True when the material had them.
bool restorePenumbraMaterial(const tinygltf::Material& m, const std::string& path, ImportedMaterial& material) {
  const nlohmann::json extras = penumbraExtras(m.extras);
  if (!extras.is_object()) return false;
  if (extras.contains("material")) {
    material.surface = protocol::materialFromJson(material.name, extras["material"], path + ".extras.penumbra.material");
    material.albedo = material.surface.albedo;
    return true;
  }
  const auto radiance = extras.find("radiance");
  if (radiance == extras.end()) return false;
  if (!radiance->is_array() || radiance->size() != 3 || !std::all_of(radiance->begin(), radiance->end(), [](const auto& v) {
        return v.is_number();
      }))
    throw ValidationError(path + ".extras.penumbra.radiance", "radiance must be three numbers");
  material.albedo = Vec3(0.0);
  material.emission = Vec3((*radiance)[0].get<double>(), (*radiance)[1].get<double>(), (*radiance)[2].get<double>());
  return true;
}

// ours: the file is Penumbra's own export (asset.extras.penumbra), whose materials carry the scene's.
std::vector<ImportedMaterial> materialsOf(const tinygltf::Model& model, bool ours, ImportReport& report) {
  std::vector<ImportedMaterial> materials;
  std::set<std::string> names;
  for (size_t i = 0; i < model.materials.size(); ++i) {
    const tinygltf::Material& m = model.materials[i];
    ImportedMaterial material;
    material.name = m.name.empty() ? "material" + std::to_string(i) : m.name;
    if (!names.insert(material.name).second) {
      material.name += "." + std::to_string(i);
      names.insert(material.name);
      report.count("material_names_made_unique");
    }
    if (ours && restorePenumbraMaterial(m, at("materials", i), material)) {
      report.count("penumbra_materials_restored");
      materials.push_back(std::move(material));
      continue;
    }
    const std::vector<double>& base = m.pbrMetallicRoughness.baseColorFactor;
    if (base.size() >= 3) material.albedo = Vec3(base[0], base[1], base[2]);
    mapMicrofacet(m, material, report);
    double strength = 1;
    const auto ext = m.extensions.find("KHR_materials_emissive_strength");
    if (ext != m.extensions.end() && ext->second.Has("emissiveStrength"))
      strength = ext->second.Get("emissiveStrength").GetNumberAsDouble();
    if (m.emissiveFactor.size() == 3)
      material.emission = strength * Vec3(m.emissiveFactor[0], m.emissiveFactor[1], m.emissiveFactor[2]);
    materials.push_back(std::move(material));
  }
  return materials;
}

// One primitive's triangles (list, strip or fan) as index triples into its positions.
std::vector<IndexPolygon> trianglesOf(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                      size_t vertexCount, const std::string& path) {
  std::vector<int> order;
  if (primitive.indices >= 0) {
    const AccessorReader indices(model, primitive.indices, path + ".indices");
    if (indices.components() != 1) throw ValidationError(path + ".indices", "indices must be scalars");
    for (size_t i = 0; i < indices.count(); ++i) {
      const double v = indices.component(i, 0);
      if (v >= double(vertexCount)) throw ValidationError(path + ".indices", "index " + std::to_string(size_t(v)) + " is past the positions");
      order.push_back(int(v));
    }
  } else {
    for (size_t i = 0; i < vertexCount; ++i) order.push_back(int(i));
  }
  std::vector<IndexPolygon> triangles;
  const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
  if (mode == TINYGLTF_MODE_TRIANGLES) {
    for (size_t i = 0; i + 2 < order.size(); i += 3) triangles.push_back({order[i], order[i + 1], order[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
    for (size_t i = 0; i + 2 < order.size(); ++i)
      triangles.push_back(i % 2 ? IndexPolygon{order[i + 1], order[i], order[i + 2]}
                                : IndexPolygon{order[i], order[i + 1], order[i + 2]});
  } else if (mode == TINYGLTF_MODE_TRIANGLE_FAN) {
    for (size_t i = 1; i + 1 < order.size(); ++i) triangles.push_back({order[0], order[i], order[i + 1]});
  }
  return triangles;
}

// A primitive's positions (its own space) and triangles: Draco-decoded, or read from its
// accessors (float, or integers as KHR_mesh_quantization stores them).
DecodedPrimitive primitiveGeometry(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                   const std::string& path, ImportReport& report) {
  if (auto decoded = decodeDracoPrimitive(model, primitive, path)) {
    report.count("draco_compressed_primitives");
    return std::move(*decoded);
  }
  const auto position = primitive.attributes.find("POSITION");
  if (position == primitive.attributes.end()) throw ValidationError(path + ".attributes", "primitive has no POSITION");
  const AccessorReader positions(model, position->second, path + ".attributes.POSITION");
  if (positions.components() != 3) throw ValidationError(path + ".attributes.POSITION", "POSITION must be VEC3");
  DecodedPrimitive out;
  for (size_t i = 0; i < positions.count(); ++i)
    out.positions.push_back(Vec3(positions.component(i, 0), positions.component(i, 1), positions.component(i, 2)));
  out.triangles = trianglesOf(model, primitive, positions.count(), path);
  // Shading normals, one per position (ignored unless VEC3 with a count matching POSITION).
  if (const auto normal = primitive.attributes.find("NORMAL"); normal != primitive.attributes.end()) {
    const AccessorReader normals(model, normal->second, path + ".attributes.NORMAL");
    if (normals.components() == 3 && normals.count() == positions.count())
      for (size_t i = 0; i < normals.count(); ++i)
        out.normals.push_back(Vec3(normals.component(i, 0), normals.component(i, 1), normals.component(i, 2)));
    else
      report.count("normals_ignored");
  }
  return out;
}

// Penumbra's export names each vertex's scene face (_FACE): each face is rebuilt whole from its
// triangles instead of joining coplanar triangles as for any file.
void restoreSceneFaces(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const std::string& path,
                       ImportedGroup& group, ImportReport& report) {
  const auto attribute = primitive.attributes.find(kFaceAttribute);
  if (attribute == primitive.attributes.end() || primitive.extensions.count("KHR_draco_mesh_compression")) return;
  const AccessorReader faceOf(model, attribute->second, path + ".attributes." + kFaceAttribute);
  if (faceOf.components() != 1 || faceOf.count() != group.positions.size())
    throw ValidationError(path + ".attributes." + kFaceAttribute, "must be one number per position");
  std::vector<double> faces(faceOf.count());
  for (size_t i = 0; i < faces.size(); ++i) faces[i] = faceOf.component(i, 0);
  if (auto restored = facesFromTriangles(group.positions, group.polygons, faces)) {
    report.count("penumbra_faces_restored", restored->size());
    group.trianglesRead = group.polygons.size();
    group.polygons = std::move(*restored);
    group.cornerNormals.clear();  // per triangle, not per restored face
    group.joinTriangles = false;
  }
}

// A primitive whose material has a base colour texture gets a material of its own: albedo =
// base colour factor × the texture's average over its triangles (texture_average.h), stated
// in the report's warnings. Without its TEXCOORD, a decoded image, or with Draco, the texture is
// ignored (counted).
void applyBaseColourTexture(const tinygltf::Model& model, const tinygltf::Primitive& primitive, const std::string& path,
                            ImportedGeometry& geometry, ImportedGroup& group, ImportReport& report) {
  if (primitive.material < 0) return;
  const tinygltf::TextureInfo& info = model.materials[size_t(primitive.material)].pbrMetallicRoughness.baseColorTexture;
  if (info.index < 0) return;
  const int source = size_t(info.index) < model.textures.size() ? model.textures[size_t(info.index)].source : -1;
  const auto uvAttribute = primitive.attributes.find("TEXCOORD_" + std::to_string(info.texCoord));
  if (source < 0 || size_t(source) >= model.images.size() || model.images[size_t(source)].image.empty() ||
      uvAttribute == primitive.attributes.end() || primitive.extensions.count("KHR_draco_mesh_compression")) {
    report.count("textures_ignored");
    return;
  }
  const AccessorReader uv(model, uvAttribute->second, path + ".attributes." + uvAttribute->first);
  if (uv.components() != 2 || uv.count() != group.positions.size())
    throw ValidationError(path + ".attributes." + uvAttribute->first, "must be one VEC2 per position");
  std::vector<Vec2> uvs;
  for (size_t i = 0; i < uv.count(); ++i) {
    const Vec2 p(uv.component(i, 0), uv.component(i, 1));
    uvs.push_back(std::isfinite(p.x) && std::isfinite(p.y) ? p : Vec2(0.0));  // a broken UV samples a corner
  }
  const auto average = averageTextureColour(model.images[size_t(source)], uvs, group.positions, group.polygons);
  if (!average) return report.count("textures_ignored");
  ImportedMaterial material = geometry.materials[size_t(group.material)];
  material.albedo *= *average;
  material.name += "." + group.name;
  geometry.materials.push_back(material);
  group.material = int(geometry.materials.size() - 1);
  report.count("textures_averaged_into_albedo");
  std::ostringstream line;
  line.precision(4);
  line << "'" << group.name << "': base colour texture averaged over its faces: albedo (" << material.albedo.x << ", "
       << material.albedo.y << ", " << material.albedo.z << ")";
  report.warnings.push_back(line.str());
}

ImportResult importModel(const tinygltf::Model& model, const std::string& warn, const ImportOptions& options,
                         ImportReport report) {
  for (size_t start = 0; start < warn.size();) {
    const size_t end = std::min(warn.find('\n', start), warn.size());
    if (end > start) report.warnings.push_back(warn.substr(start, end - start));
    start = end + 1;
  }
  // Penumbra's own export: its faces, materials and camera come back (penumbra_extras.h).
  const bool ours = penumbraExtras(model.asset.extras).is_object();
  ImportedGeometry geometry;
  geometry.materials = materialsOf(model, ours, report);
  // Shadows are of one pose: the nodes' own transforms (bind pose), nothing moved or morphed.
  if (!model.skins.empty()) {
    report.count("skins_ignored", model.skins.size());
    report.warnings.push_back("skins ignored: skinned meshes are imported as stored (bind pose), joints not applied");
  }
  if (!model.animations.empty()) {
    report.count("animations_ignored", model.animations.size());
    report.warnings.push_back("animations ignored: the scene is imported with its nodes' own transforms");
  }
  std::vector<bool> sceneDefault;  // Penumbra's default material: no material in the scene
  for (const tinygltf::Material& m : model.materials) {
    const nlohmann::json extras = penumbraExtras(m.extras);
    sceneDefault.push_back(ours && extras.is_object() && extras.value("default_material", false));
  }

  std::vector<int> roots;
  if (!model.scenes.empty()) {
    const size_t scene = model.defaultScene >= 0 && size_t(model.defaultScene) < model.scenes.size()
                             ? size_t(model.defaultScene) : 0;
    roots = model.scenes[scene].nodes;
  } else {
    std::set<int> children;
    for (const tinygltf::Node& node : model.nodes) children.insert(node.children.begin(), node.children.end());
    for (size_t i = 0; i < model.nodes.size(); ++i)
      if (!children.count(int(i))) roots.push_back(int(i));
  }

  std::function<void(int, const Mat4&, int)> visit = [&](int index, const Mat4& parent, int depth) {
    const std::string path = at("nodes", size_t(std::max(index, 0)));
    if (index < 0 || size_t(index) >= model.nodes.size()) throw ValidationError(path, "no such node");
    if (depth > kMaxNodeDepth) throw ValidationError(path, "nodes nest deeper than 64 (a cycle?)");
    const tinygltf::Node& node = model.nodes[size_t(index)];
    if (const nlohmann::json extras = penumbraExtras(node.extras); ours && extras.is_object() && extras.contains("camera"))
      geometry.camera = extras["camera"];
    const Mat4 worldFromNode = parent * localMatrix(node);
    if (node.mesh >= 0) {
      if (size_t(node.mesh) >= model.meshes.size()) throw ValidationError(path + ".mesh", "no such mesh");
      const tinygltf::Mesh& mesh = model.meshes[size_t(node.mesh)];
      const bool mirrored = glm::determinant(Mat3(worldFromNode)) < 0;
      for (size_t p = 0; p < mesh.primitives.size(); ++p) {
        const tinygltf::Primitive& primitive = mesh.primitives[p];
        const std::string primitivePath = at(at("meshes", size_t(node.mesh)) + ".primitives", p);
        const int mode = primitive.mode < 0 ? TINYGLTF_MODE_TRIANGLES : primitive.mode;
        if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
            mode != TINYGLTF_MODE_TRIANGLE_FAN) {
          report.count("point_and_line_primitives_skipped");
          continue;
        }
        ImportedGroup group;
        group.name = !node.name.empty() ? node.name : !mesh.name.empty() ? mesh.name : "mesh" + std::to_string(node.mesh);
        if (primitive.material >= int(geometry.materials.size()))
          throw ValidationError(primitivePath + ".material", "no such material");
        group.material = primitive.material >= 0 && sceneDefault[size_t(primitive.material)] ? -1 : primitive.material;
        group.joinTriangles = true;
        if (!primitive.targets.empty()) report.count("morph_targets_ignored", primitive.targets.size());
        DecodedPrimitive local = primitiveGeometry(model, primitive, primitivePath, report);
        for (const Vec3& p : local.positions) group.positions.push_back(Vec3(worldFromNode * glm::dvec4(p, 1.0)));
        group.polygons = std::move(local.triangles);
        if (!local.normals.empty()) {  // normals map by the inverse transpose
          const Mat3 normalFromNode = glm::transpose(glm::inverse(Mat3(worldFromNode)));
          for (const IndexPolygon& t : group.polygons) {
            std::vector<Vec3>& corners = group.cornerNormals.emplace_back();
            for (int i : t) corners.push_back(normalFromNode * local.normals[size_t(i)]);
          }
        }
        if (group.material >= 0)
          applyBaseColourTexture(model, primitive, primitivePath, geometry, group, report);
        if (mirrored)  // glTF: a mirroring transform flips the winding back
          for (size_t t = 0; t < group.polygons.size(); ++t) {
            std::swap(group.polygons[t][1], group.polygons[t][2]);
            if (t < group.cornerNormals.size()) std::swap(group.cornerNormals[t][1], group.cornerNormals[t][2]);
          }
        if (ours) restoreSceneFaces(model, primitive, primitivePath, group, report);
        geometry.groups.push_back(std::move(group));
      }
    }
    for (int child : node.children) visit(child, worldFromNode, depth + 1);
  };
  for (int root : roots) visit(root, Mat4(1.0), 0);
  return assembleScene(geometry, options, std::move(report));
}

ImportResult importGltf(const std::vector<uint8_t>& bytes, const std::string& baseDir, bool allowFiles,
                        const ImportOptions& options, const std::string& sourceName) {
  if (bytes.size() > kMaxGltfBytes) throw ValidationError("(gltf)", "the file is over the limit of 256 MiB");
  tinygltf::TinyGLTF loader;
  size_t pixelsLeft = kMaxTexturePixels;
  loader.SetImageLoader(loadImageWithinBudget, &pixelsLeft);
  if (!allowFiles) loader.SetFsCallbacks(tinygltf::FsCallbacks{noFile, samePath, noRead, noWrite, nullptr});
  tinygltf::Model model;
  std::string err, warn;
  ImportReport report;
  report.source = sourceName;
  const bool binary = isBinary(bytes);
  report.format = binary ? "glb" : "gltf";
  const std::vector<uint8_t> readable = readableByTinygltf(bytes);
  const bool ok = binary ? loader.LoadBinaryFromMemory(&model, &err, &warn, readable.data(), unsigned(readable.size()), baseDir)
                         : loader.LoadASCIIFromString(&model, &err, &warn, reinterpret_cast<const char*>(readable.data()),
                                                      unsigned(readable.size()), baseDir);
  if (!ok) throw ValidationError("(gltf)", err.empty() ? "tinygltf could not read the file" : err);
  checkRequiredExtensions(model);
  report.count("meshopt_compressed_buffer_views", decodeMeshoptViews(model));
  return importModel(model, warn, options, std::move(report));
}

}  // namespace

ImportResult importGltfFile(const std::string& path, const ImportOptions& options) {
  const std::filesystem::path file(path);
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path);
  if (std::filesystem::file_size(file) > kMaxGltfBytes)
    throw ValidationError("(gltf)", file.filename().string() + " is over the limit of 256 MiB");
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string baseDir = file.parent_path().empty() ? "." : file.parent_path().string();
  return importGltf(bytes, baseDir, /*allowFiles=*/true, options, file.filename().string());
}

ImportResult importGltfBytes(const std::vector<uint8_t>& bytes, const ImportOptions& options,
                             const std::string& sourceName) {
  // Only embedded buffers (GLB, data: URIs) resolve.
  return importGltf(bytes, "", /*allowFiles=*/false, options, sourceName);
}

}  // namespace penumbra::interchange
