// A file's shading normals (OBJ `vn`, glTF NORMAL) carried through welding and repairs to the
// imported objects' corner normals (Object::normals, core/scene/shading_normal.h). Repairs
// split, join and re-orient polygons, so normals are gathered per welded position and each
// assembled face corner takes the mean of those there that lie within 60° of the face's
// normal: a smooth file's normal where the position has one, each side's own at a crease.
// Pure functions; thread-safe.
#pragma once

#include <vector>

#include <nlohmann/json.hpp>

#include "core/geom/vec.h"
#include "interchange/imported_geometry.h"

namespace penumbra::interchange {

// Per welded position (`remap`: the group's position → welded index), the file's unit normals
// at its corners; empty when the group has none.
std::vector<std::vector<Vec3>> fileNormalsAt(const ImportedGroup& group, const std::vector<int>& remap,
                                             size_t weldedCount);

// The corner normals of `faces` (indices into `positions`) as scene JSON (one list per face);
// a corner with no file normal within 60° of its face takes the face's own normal, counted in
// `flatCorners`.
nlohmann::json cornerNormalsJson(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces,
                                 const std::vector<std::vector<Vec3>>& normalsAt, size_t& flatCorners);

}  // namespace penumbra::interchange
