#include "interchange/obj_import.h"

#include "interchange/material_mapping.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <fstream>
#include <regex>
#include <sstream>

#include <tiny_obj_loader.h>

#include "protocol/validation_error.h"

namespace penumbra::interchange {

namespace {

using protocol::ValidationError;

constexpr size_t kMaxObjBytes = size_t(256) << 20;
// Placeholder key on materials that 'usemtl' names but no MTL file defines.
constexpr const char* kUndefinedKey = "penumbra_undefined";
// The first line we put before the file so every material is known before any usemtl.
constexpr const char* kMaterialsLine = "mtllib penumbra-materials\n";

std::string readFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + path.string());
  if (std::filesystem::file_size(path) > kMaxObjBytes)
    throw ValidationError("(obj)", path.filename().string() + " is over the limit of 256 MiB");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

struct ObjDirectives {
  std::vector<std::string> mtllibs;  // in order, each once
  std::vector<std::string> usemtls;  // each once
  size_t crlfLines = 0;
  // Every 'v' line's x, y, z as strtod reads them (correctly rounded; tinyobjloader's
  // own parser can be an ulp off); `exactVertices` false if some line lacks one.
  std::vector<double> vertices;
  bool exactVertices = true;
};

// Up to `count` numbers from the rest of a line, by strtod.
std::vector<double> numbers(const std::string& line, size_t from, size_t count) {
  std::vector<double> out;
  const char* p = line.c_str() + from;
  while (out.size() < count) {
    char* end = nullptr;
    const double value = std::strtod(p, &end);
    if (end == p) break;
    out.push_back(value);
    p = end;
  }
  return out;
}

// Kd, Ka, Ke of each material in MTL text, read exactly (see ObjDirectives::vertices), and
// whether it has an Ns line (tinyobjloader gives a missing Ns the exponent 1: α 0.82, not the default).
struct ExactColors {
  std::optional<Vec3> kd, ka, ke;
  bool ns = false;
};
std::map<std::string, ExactColors> exactColors(const std::string& mtlText) {
  std::map<std::string, ExactColors> colors;
  std::istringstream in(mtlText);
  std::string line, current;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "newmtl") {
      words >> current;
      continue;
    }
    if (!current.empty() && keyword == "Ns") colors[current].ns = true;
    if (current.empty() || (keyword != "Kd" && keyword != "Ka" && keyword != "Ke")) continue;
    const std::vector<double> rgb = numbers(line, line.find(keyword) + 2, 3);
    if (rgb.size() != 3) continue;  // tinyobjloader's reading stands
    ExactColors& c = colors[current];
    (keyword == "Kd" ? c.kd : keyword == "Ka" ? c.ka : c.ke) = Vec3(rgb[0], rgb[1], rgb[2]);
  }
  return colors;
}

// The few directives we need before tinyobjloader runs.
ObjDirectives scanDirectives(const std::string& text) {
  ObjDirectives found;
  std::istringstream in(text);
  std::string line;
  auto addOnce = [](std::vector<std::string>& list, const std::string& name) {
    if (std::find(list.begin(), list.end(), name) == list.end()) list.push_back(name);
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') {
      line.pop_back();
      ++found.crlfLines;
    }
    std::istringstream words(line);
    std::string keyword, name;
    words >> keyword;
    if (keyword == "v") {
      const std::vector<double> xyz = numbers(line, line.find('v') + 1, 3);
      if (xyz.size() == 3) found.vertices.insert(found.vertices.end(), xyz.begin(), xyz.end());
      else found.exactVertices = false;
    } else if (keyword == "mtllib") {
      while (words >> name) addOnce(found.mtllibs, name);
    } else if (keyword == "usemtl" && (words >> name)) {
      addOnce(found.usemtls, name);  // tinyobjloader keeps the first word too
    }
  }
  return found;
}

// Hands tinyobjloader every material at once (on the line we prepend): those of
// the MTL files we have, then a placeholder for each name no file defines.
class PreparedMaterials : public tinyobj::MaterialReader {
 public:
  PreparedMaterials(std::string mtlText, std::vector<std::string> usemtls)
      : mtlText_(std::move(mtlText)), usemtls_(std::move(usemtls)) {}

  bool operator()(const std::string&, std::vector<tinyobj::material_t>* materials,
                  std::map<std::string, int>* byName, std::string* warn, std::string* err) override {
    if (done_) return true;  // the file's own mtllib lines: already loaded
    done_ = true;
    std::istringstream in(mtlText_);
    tinyobj::LoadMtl(byName, materials, &in, warn, err);
    for (const std::string& name : usemtls_) {
      if (byName->count(name)) continue;
      tinyobj::material_t placeholder{};  // value-initialised: the type has no constructor
      placeholder.name = name;
      placeholder.unknown_parameter[kUndefinedKey] = "1";
      (*byName)[name] = int(materials->size());
      materials->push_back(placeholder);
    }
    return true;
  }

 private:
  std::string mtlText_;
  std::vector<std::string> usemtls_;
  bool done_ = false;
};

// tinyobjloader's line numbers count the line we prepended.
std::string fileLineNumbers(const std::string& message) {
  std::string out;
  const std::regex lineNumber(R"(line (\d+))");
  auto begin = std::sregex_iterator(message.begin(), message.end(), lineNumber);
  size_t last = 0;
  for (auto it = begin; it != std::sregex_iterator(); ++it) {
    out += message.substr(last, size_t(it->position()) - last);
    out += "line " + std::to_string(std::stol((*it)[1].str()) - 1);
    last = size_t(it->position() + it->length());
  }
  return out + message.substr(last);
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.find_first_not_of(" \t\r.") != std::string::npos) out.push_back(line);
  return out;
}

Vec3 vec3(const tinyobj::real_t* v) { return Vec3(v[0], v[1], v[2]); }
bool positive(const Vec3& v) { return v.x > 0 || v.y > 0 || v.z > 0; }

ImportedMaterial materialFrom(const tinyobj::material_t& m, const ExactColors& exact, const ImportOptions& options,
                              ImportReport& report) {
  ImportedMaterial material;
  material.name = m.name;
  if (m.unknown_parameter.count(kUndefinedKey)) {
    material.defined = false;
    report.count("undefined_materials");
    // A light's material in a lost MTL file: a light only if told its radiance.
    if (namedLikeALight(m.name) && options.lightRadiance) material.emission = *options.lightRadiance;
    return material;
  }
  material.albedo = exact.kd.value_or(vec3(m.diffuse));
  // PBR extension Pm/Pr, transparency d/Tr with Ni; Ns gives the roughness without Pr.
  const double alpha = m.roughness > 0 ? alphaFromPerceptual(m.roughness)
                       : exact.ns && m.shininess > 0 ? alphaFromPhong(m.shininess) : Material{}.roughness.x;
  if (m.metallic >= 0.5) {
    setConductorFromBaseColor(material.surface, material.albedo);
    material.surface.roughness = Vec2(alpha);
    report.count("materials_mapped_to_conductor");
  } else if (m.dissolve < 1) {
    material.surface.type = MaterialType::Dielectric;
    material.surface.roughness = Vec2(alpha);
    material.surface.ior = m.ior > 1 && m.ior <= 4 ? m.ior : 1.5;
    report.count("materials_mapped_to_dielectric");
  }
  const Vec3 emission = exact.ke.value_or(vec3(m.emission)), ambient = exact.ka.value_or(vec3(m.ambient));
  if (positive(emission)) {
    material.emission = emission;
  } else if (namedLikeALight(m.name) && positive(ambient)) {
    material.emission = ambient;
    report.count("light_radiance_taken_from_ka");
  }
  return material;
}

}  // namespace

bool namedLikeALight(const std::string& materialName) {
  std::string lower = materialName;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  return lower.find("light") != std::string::npos || lower.find("lamp") != std::string::npos ||
         lower.find("emit") != std::string::npos;
}

ImportResult importObjFile(const std::string& path, const ImportOptions& options) {
  const std::filesystem::path file(path);
  const std::string text = readFile(file);
  std::map<std::string, std::string> mtlFiles;
  for (const std::string& name : scanDirectives(text).mtllibs) {
    const std::filesystem::path mtl = file.parent_path() / name;
    std::error_code error;
    if (std::filesystem::is_regular_file(mtl, error)) mtlFiles[name] = readFile(mtl);
  }
  return importObjText(text, mtlFiles, options, file.filename().string());
}

ImportResult importObjText(const std::string& objText, const std::map<std::string, std::string>& mtlFiles,
                           const ImportOptions& options, const std::string& sourceName) {
  if (objText.size() > kMaxObjBytes) throw ValidationError("(obj)", "the OBJ text is over the limit of 256 MiB");
  ImportReport report;
  report.source = sourceName;
  report.format = "obj";

  const ObjDirectives directives = scanDirectives(objText);
  report.count("crlf_line_endings_read", directives.crlfLines);
  std::string mtlText;
  for (const std::string& name : directives.mtllibs) {
    const auto it = mtlFiles.find(name);
    if (it == mtlFiles.end()) {
      report.count("missing_material_files");
      report.warnings.push_back("material file '" + name + "' not found: its materials take the default albedo");
      continue;
    }
    mtlText += it->second + "\n";
  }

  PreparedMaterials materialReader(mtlText, directives.usemtls);
  std::istringstream in(kMaterialsLine + objText);
  tinyobj::attrib_t attrib;
  std::vector<tinyobj::shape_t> shapes;
  std::vector<tinyobj::material_t> materials;
  std::string warn, err;
  const bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &in, &materialReader,
                                   /*triangulate=*/false, /*default_vcols_fallback=*/false);
  if (!ok) throw ValidationError("(obj)", fileLineNumbers(err.empty() ? "tinyobjloader failed" : err));
  for (const std::string& line : lines(fileLineNumbers(warn))) {
    if (line.find("Degenerated face") != std::string::npos) {
      report.count("degenerate_polygons_dropped");
      continue;
    }
    if (line.find("out of bounds") != std::string::npos && line.find("Vertex indices") != std::string::npos)
      throw ValidationError("(obj)", line);
    report.warnings.push_back(line);
  }

  ImportedGeometry geometry;
  const std::map<std::string, ExactColors> colors = exactColors(mtlText);
  for (const tinyobj::material_t& m : materials) {
    const auto exact = colors.find(m.name);
    geometry.materials.push_back(materialFrom(m, exact == colors.end() ? ExactColors{} : exact->second, options, report));
  }

  const size_t vertexCount = attrib.vertices.size() / 3;
  const bool exactVertices = directives.exactVertices && directives.vertices.size() == attrib.vertices.size();
  auto position = [&](int v) {
    const size_t at = size_t(v) * 3;
    return exactVertices ? Vec3(directives.vertices[at], directives.vertices[at + 1], directives.vertices[at + 2])
                         : vec3(&attrib.vertices[at]);
  };
  for (const tinyobj::shape_t& shape : shapes) {
    // One group per material the shape uses, in first-use order.
    std::map<int, size_t> groupOfMaterial;
    const size_t firstGroup = geometry.groups.size();
    std::vector<std::map<int, int>> localIndex;
    size_t offset = 0;
    for (size_t f = 0; f < shape.mesh.num_face_vertices.size(); ++f) {
      const size_t count = shape.mesh.num_face_vertices[f];
      const int material = f < shape.mesh.material_ids.size() ? shape.mesh.material_ids[f] : -1;
      auto [it, fresh] = groupOfMaterial.emplace(material, geometry.groups.size());
      if (fresh) {
        ImportedGroup group;
        group.name = shape.name;
        group.material = material;
        geometry.groups.push_back(std::move(group));
        localIndex.emplace_back();
      }
      ImportedGroup& group = geometry.groups[it->second];
      std::map<int, int>& local = localIndex[it->second - firstGroup];
      IndexPolygon polygon;
      std::vector<Vec3> normals;
      for (size_t k = 0; k < count; ++k) {
        const int vn = shape.mesh.indices[offset + k].normal_index;
        if (vn >= 0 && size_t(vn) * 3 + 2 < attrib.normals.size()) normals.push_back(vec3(&attrib.normals[size_t(vn) * 3]));
        const int v = shape.mesh.indices[offset + k].vertex_index;
        if (v < 0 || size_t(v) >= vertexCount)
          throw ValidationError("(obj)", "object '" + shape.name + "' face " + std::to_string(f) +
                                             " refers to vertex " + std::to_string(v + 1) + ", the file has " +
                                             std::to_string(vertexCount));
        const auto [at, added] = local.emplace(v, int(group.positions.size()));
        if (added) group.positions.push_back(position(v));
        polygon.push_back(at->second);
      }
      offset += count;
      group.polygons.push_back(std::move(polygon));
      // Normals on every corner or none (a face with some `vn` missing is shaded flat).
      if (normals.size() != count) normals.clear();
      if (!normals.empty() && group.cornerNormals.size() < group.polygons.size() - 1)
        group.cornerNormals.resize(group.polygons.size() - 1);
      if (!normals.empty() || !group.cornerNormals.empty()) group.cornerNormals.push_back(std::move(normals));
    }
    if (groupOfMaterial.size() > 1) {
      report.count("groups_split_by_material", groupOfMaterial.size() - 1);
      for (size_t g = firstGroup; g < geometry.groups.size(); ++g) {
        const int m = geometry.groups[g].material;
        geometry.groups[g].name += "." + (m >= 0 ? materials[size_t(m)].name : std::string("default"));
      }
    }
  }
  return assembleScene(geometry, options, std::move(report));
}

}  // namespace penumbra::interchange
