// What an import changed in its input: one counter per kind of repair (or of finding
// left as it was, like coplanar overlaps), the warnings, and the size of the result.
// Plain value filled by one importer; not shared between threads while it is being filled.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace penumbra::interchange {

struct ImportReport {
  std::string source;  // the input's file name
  std::string format;  // "obj", "gltf" or "glb"
  // Repair name → how many times it was made (README "Import" lists the names).
  // Only repairs that happened appear; nothing is ever changed without a count here.
  std::map<std::string, size_t> repairs;
  // The loader's, verbatim, and the importer's (missing files, coplanar overlaps), one per line.
  std::vector<std::string> warnings;
  size_t objects = 0, faces = 0, lights = 0, materials = 0;

  void count(const std::string& repair, size_t times = 1) {
    if (times) repairs[repair] += times;
  }
  size_t repaired(const std::string& repair) const {
    const auto it = repairs.find(repair);
    return it == repairs.end() ? 0 : it->second;
  }

  // {"source", "format", "objects", "faces", "lights", "materials", "repairs": {...}, "warnings": [...]}
  nlohmann::json toJson() const;
  // A few human lines for stderr: the result's size, then one line per repair.
  std::string summary() const;
};

}  // namespace penumbra::interchange
