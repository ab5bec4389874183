// What a format reader hands to scene assembly: named polygon groups with a
// material each, and the materials (albedo, emitted radiance). Plain data, built by
// one reader; thread-safe to read.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geom/vec.h"
#include "core/scene/scene.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {

struct ImportedMaterial {
  std::string name;
  Vec3 albedo{0.8};
  Vec3 emission{0.0};  // radiance, W·m⁻²·sr⁻¹; non-zero makes its polygons lights
  bool defined = true;  // false: named by the file but found in no material file
  Material surface;     // the microfacet keys (type diffuse unless mapped; its albedo unused)
};

struct ImportedGroup {
  std::string name;   // may be empty or repeated; assembly makes ids unique
  int material = -1;  // index into ImportedGeometry::materials, -1 = none
  std::vector<Vec3> positions;  // file units (assembly applies ImportOptions::scale)
  std::vector<IndexPolygon> polygons;
  // The file's shading normals (OBJ `vn`, glTF NORMAL), per polygon one per corner; empty, or
  // an empty entry for a polygon given none. Assembly turns them into corner normals.
  std::vector<std::vector<Vec3>> cornerNormals;
  // glTF: triangles of one surface are joined back into convex polygons.
  bool joinTriangles = false;
  // The file's triangles when `polygons` are not what it held (Penumbra's faces rebuilt from
  // their display triangles); unset: Σ (corners − 2) over `polygons` (ImportReport::trianglesRead).
  std::optional<size_t> trianglesRead;
};

struct ImportedGeometry {
  std::vector<ImportedMaterial> materials;
  std::vector<ImportedGroup> groups;
  // Penumbra's own GLB: its scene's camera as scene v1 writes it (file units); null otherwise.
  nlohmann::json camera;
};

struct ImportOptions {
  double scale = 1;                  // multiplies every coordinate (e.g. 0.001 for millimetres)
  std::optional<Vec3> lightRadiance;  // replaces every light's radiance (and is the studio light's)
  // A file with no emissive faces goes into the default studio (default_studio.h); false keeps
  // such a file an error ("no emissive faces").
  bool studio = true;
};

}  // namespace penumbra::interchange
