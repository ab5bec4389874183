// Generator of model scenes: one procedural tessellated model (scenegen/*_mesh.h) in the
// dense room (scenegen/dense_scene.h) under its 1 m² ceiling light, floating or resting
// on the floor, or a furnished room of nine of them and two tables. Pure; thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "scenegen/tri_mesh.h"

namespace penumbra {

enum class ModelKind { Teapot, TorusKnot, Blob, Bowl, Scan, Furnished };

// "teapot", "torus-knot", "blob", "bowl", "scan", "furnished"; nullopt for other names.
std::optional<ModelKind> modelKindFromName(const std::string& name);
const char* modelKindName(ModelKind kind);
// The names above joined by '|', for usage texts.
std::string modelKindNames();

// Triangles asked for when none are given: 6,000 for a model, 70,000 for the scan-like
// blob, 100,000 for the furnished room. Requests must lie in [minModelTriangles(kind),
// kMaxModelTriangles]: at least 200, the scan 1,000 (its counts step by 20·(2f + 1): below,
// a step is more than ±25 %), the furnished room 4,000.
int defaultModelTriangles(ModelKind kind);
int minModelTriangles(ModelKind kind);
inline constexpr int kMinModelTriangles = 200;  // the least of minModelTriangles
inline constexpr int kMaxModelTriangles = 300000;

// Whether the kind's mesh is closed (watertight, consistently oriented): the torus knot,
// the blob and the scan are; the teapot (scenegen/teapot_mesh.h) and the bowl are open.
bool modelIsClosed(ModelKind kind);

// One model's mesh, about `triangles` triangles, in its own units (not Furnished).
TriMesh modelMesh(ModelKind kind, int triangles, uint64_t seed);

struct ModelSceneOptions {
  ModelKind kind = ModelKind::Teapot;
  int triangles = 0;  // 0: defaultModelTriangles(kind)
  bool rest = false;  // on the floor (lowest vertex at y = 0) instead of floating
  bool smooth = false;  // the models carry corner normals (smoothCornerNormals, crease 60°)
  uint64_t seed = 1;  // the blob's and the scan's shapes
};

// The room [-3, 3] × [0, 3] × [-3, 3] ("floor", "ceiling", "wall_*") and:
// - a model: one object named after it ("teapot", "torus_knot", "blob", "bowl", "scan";
//   material "clay"), the teapot 0.6 m high, the others scaled so their largest side is
//   0.7 m (knot, scan) or 0.6 m (blob, bowl); its bounds centred at (0, 1, 0), or with
//   `rest` at x = z = 0 with its lowest vertex at y = 0 exactly (touching the floor).
// - Furnished (`rest` refused: each object has its own place): "table_1", "table_2"
//   (boxes 0.75 m high) and nine models apart from each other and the walls — a teapot on
//   each of table_1 and the floor, a blob on table_2 and one floating, two torus knots
//   (floating, on the floor), two bowls (on the floor, floating) and the scan on the floor
//   under the light — sharing `triangles` (scan 40 %, each teapot and bowl 6.5 %, each
//   knot 8 %, each blob 9 %). Models on a table touch its top; no bounds overlap.
// Throws std::invalid_argument for triangles outside the bounds above.
Scene makeModelScene(const ModelSceneOptions& options);

}  // namespace penumbra
