// What an import changed in its input: one counter per kind of repair (or of finding
// left as it was, like coplanar overlaps), the warnings, and the size of the result.
// Plain value filled by one importer; not shared between threads while it is being filled.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geom/vec.h"

namespace penumbra::interchange {

// One object's faces as a surface after the repairs (mesh_orientation.h says the terms).
struct ObjectMeshFacts {
  std::string object;  // its id in the scene
  size_t faces = 0;
  size_t verticesWelded = 0;  // used vertices that joined one at the same position
  size_t components = 0, closedComponents = 0;
  size_t facesFlipped = 0;      // to agree with their neighbours, or to face outward
  size_t nonManifoldEdges = 0;  // shared by 3+ faces: left as they are
  size_t boundaryEdges = 0;     // of one face only

  // "'cube': 6 faces, 1 component, 1 closed; 1 face flipped; 24 vertices welded".
  std::string sentence() const;
};

// Where a model without lights was put (default_studio.h).
struct StudioFacts {
  double scale = 1;     // applied after --scale
  Vec3 offset{0.0};     // then added: studio position = position × scale + offset
  std::string sentence;  // the account, one sentence
};

struct ImportReport {
  std::string source;  // the input's file name
  std::string format;  // "obj", "gltf" or "glb"
  // Repair name → how many times it was made (README "Import" lists the names).
  // Only repairs that happened appear; nothing is ever changed without a count here.
  std::map<std::string, size_t> repairs;
  // The loader's, verbatim, and the importer's (missing files, coplanar overlaps), one per line.
  std::vector<std::string> warnings;
  size_t objects = 0, faces = 0, lights = 0, materials = 0;
  // What the reader read, before any repair: triangles = Σ (corners − 2) over the file's
  // polygons (a triangle list counts its triangles), and the bounds of the corners they use
  // (after --scale, before the studio). Another reader's counts compare with these (issue 40).
  size_t trianglesRead = 0;
  Vec3 boundsMin{0.0}, boundsMax{0.0};
  // The model's objects (not the studio's), in scene order.
  std::vector<ObjectMeshFacts> meshes;
  std::optional<StudioFacts> studio;  // set when the file had no lights and went into the studio

  void count(const std::string& repair, size_t times = 1) {
    if (times) repairs[repair] += times;
  }
  size_t repaired(const std::string& repair) const {
    const auto it = repairs.find(repair);
    return it == repairs.end() ? 0 : it->second;
  }

  // {"source", "format", "objects", "faces", "lights", "materials", "repairs": {...}, "warnings": [...],
  //  "triangles_read", "bounds": {"min", "max"},
  //  "meshes": [{"object", "faces", "vertices_welded", "components", "closed_components", "faces_flipped",
  //              "non_manifold_edges", "boundary_edges"}, ...], and "studio": {"scale", "offset", "sentence"}
  //  when it was used}
  nlohmann::json toJson() const;
  // A few human lines for stderr: the result's size, the studio's sentence, one line per object's
  // surface, then one line per repair.
  std::string summary() const;
};

}  // namespace penumbra::interchange
