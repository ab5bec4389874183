#include "scenegen/model_scene.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

#include "scenegen/blob_mesh.h"
#include "scenegen/bowl_mesh.h"
#include "scenegen/dense_scene.h"
#include "scenegen/scan_mesh.h"
#include "scenegen/scene_parts.h"
#include "scenegen/teapot_mesh.h"
#include "scenegen/torus_knot_mesh.h"

namespace penumbra {

namespace {

constexpr ModelKind kKinds[] = {ModelKind::Teapot, ModelKind::TorusKnot, ModelKind::Blob,
                                ModelKind::Bowl,   ModelKind::Scan,      ModelKind::Furnished};

// How a model is sized: the teapot by its height, the others by their largest side.
double modelScale(ModelKind kind, const TriMesh& mesh, double size) {
  const Vec3 extent = meshBounds(mesh).size();
  const double measured =
      kind == ModelKind::Teapot ? extent.y : std::max({extent.x, extent.y, extent.z});
  if (!(measured > 0)) throw std::invalid_argument("makeModelScene: a model without extent");
  return size / measured;
}

double singleModelSize(ModelKind kind) {
  switch (kind) {
    case ModelKind::Teapot:
      return 0.6;
    case ModelKind::TorusKnot:
    case ModelKind::Scan:
      return 0.7;
    default:
      return 0.6;
  }
}

std::string objectName(ModelKind kind) {
  std::string name = modelKindName(kind);
  std::replace(name.begin(), name.end(), '-', '_');
  return name;
}

// A furnished room's model: what, its share of the triangles, size, place and seed offset.
struct Placement {
  const char* id;
  ModelKind kind;
  double share;
  double size;  // as modelScale: the teapot's height, else the largest side
  Vec3 at;      // bounds' centre, or (x, floor or table top, z) when resting
  bool rest;
  uint64_t seedOffset;
};

constexpr double kTableHeight = 0.75;

// Boxes and footprints are laid out by hand so that no two bounds overlap (the scene test
// checks it): the largest footprint half-sides are 0.52 × 0.32 m (teapots at 0.5 m high).
const Placement kFurnished[] = {
    {"teapot_1", ModelKind::Teapot, 0.065, 0.5, {-1.8, kTableHeight, -1.9}, true, 0},
    {"teapot_2", ModelKind::Teapot, 0.065, 0.5, {1.7, 0, 1.6}, true, 0},
    {"blob_1", ModelKind::Blob, 0.09, 0.5, {1.8, kTableHeight, -1.9}, true, 0},
    {"blob_2", ModelKind::Blob, 0.09, 0.5, {1.4, 1.3, 0.2}, false, 1},
    {"torus_knot_1", ModelKind::TorusKnot, 0.08, 0.7, {-1.3, 1.4, 0.6}, false, 0},
    {"torus_knot_2", ModelKind::TorusKnot, 0.08, 0.7, {-1.9, 0, 1.7}, true, 0},
    {"bowl_1", ModelKind::Bowl, 0.065, 0.6, {0.1, 0, 1.9}, true, 0},
    {"bowl_2", ModelKind::Bowl, 0.065, 0.6, {-0.2, 2.0, -1.4}, false, 0},
    {"scan", ModelKind::Scan, 0.40, 0.8, {0, 0, 0}, true, 0},
};

void checkTriangles(ModelKind kind, int triangles) {
  const int least = minModelTriangles(kind);
  if (triangles < least || triangles > kMaxModelTriangles)
    throw std::invalid_argument("makeModelScene: triangles must be in [" + std::to_string(least) +
                                ", " + std::to_string(kMaxModelTriangles) + "]");
}

}  // namespace

std::optional<ModelKind> modelKindFromName(const std::string& name) {
  for (ModelKind kind : kKinds)
    if (name == modelKindName(kind)) return kind;
  return std::nullopt;
}

const char* modelKindName(ModelKind kind) {
  switch (kind) {
    case ModelKind::Teapot:
      return "teapot";
    case ModelKind::TorusKnot:
      return "torus-knot";
    case ModelKind::Blob:
      return "blob";
    case ModelKind::Bowl:
      return "bowl";
    case ModelKind::Scan:
      return "scan";
    case ModelKind::Furnished:
      return "furnished";
  }
  return "?";
}

std::string modelKindNames() {
  std::string out;
  for (ModelKind kind : kKinds) out += (out.empty() ? "" : "|") + std::string(modelKindName(kind));
  return out;
}

int defaultModelTriangles(ModelKind kind) {
  return kind == ModelKind::Scan ? 70000 : kind == ModelKind::Furnished ? 100000 : 6000;
}

int minModelTriangles(ModelKind kind) {
  return kind == ModelKind::Scan ? 1000 : kind == ModelKind::Furnished ? 4000 : kMinModelTriangles;
}

bool modelIsClosed(ModelKind kind) {
  return kind == ModelKind::TorusKnot || kind == ModelKind::Blob || kind == ModelKind::Scan;
}

TriMesh modelMesh(ModelKind kind, int triangles, uint64_t seed) {
  switch (kind) {
    case ModelKind::Teapot:
      return teapotMesh(teapotStepsFor(triangles));
    case ModelKind::TorusKnot:
      return torusKnotMesh({.triangles = triangles});
    case ModelKind::Blob:
      return blobMesh({.triangles = triangles, .seed = seed});
    case ModelKind::Bowl:
      return bowlMesh(triangles);
    case ModelKind::Scan:
      return scanMesh({.triangles = triangles, .seed = seed});
    case ModelKind::Furnished:
      break;
  }
  throw std::invalid_argument("modelMesh: the furnished room is a scene, not one mesh");
}

Scene makeModelScene(const ModelSceneOptions& options) {
  const int triangles =
      options.triangles > 0 ? options.triangles : defaultModelTriangles(options.kind);
  checkTriangles(options.kind, triangles);
  std::vector<Light> lights{
      squareCeilingLight("light", Vec3(0, kDenseLightY, 0), kDenseLightSide, 0, Vec3(1, 0, 0))};
  std::vector<Material> materials{{"white", Vec3(0.8)}, {"clay", Vec3(0.75, 0.45, 0.3)}};
  std::vector<Object> objects = roomObjects(kDenseHalfSide, kDenseHalfSide, kDenseHeight);
  Camera camera;
  camera.position = Vec3(0, 1.6, kDenseHalfSide - 0.25);
  camera.fovYDeg = 60;
  camera.far = 8 * kDenseHalfSide;

  if (options.kind != ModelKind::Furnished) {
    const TriMesh mesh = modelMesh(options.kind, triangles, options.seed);
    const Vec3 at = options.rest ? Vec3(0.0) : Vec3(0, 1, 0);
    const TriMesh placed = placedMesh(
        mesh, modelScale(options.kind, mesh, singleModelSize(options.kind)), at, options.rest);
    objects.push_back(meshObject(objectName(options.kind), placed));
    camera.target = meshBounds(placed).centre();
  } else {
    if (options.rest)
      throw std::invalid_argument("makeModelScene: the furnished room places its own objects");
    for (const auto& [id, centreX, halfX] :
         {std::tuple{"table_1", -1.8, 0.7}, std::tuple{"table_2", 1.8, 0.6}}) {
      Object table;
      table.id = id;
      table.material = "white";
      addBox(table, Vec3(centreX - halfX, 0, -2.4), Vec3(centreX + halfX, kTableHeight, -1.4));
      objects.push_back(std::move(table));
    }
    for (const Placement& p : kFurnished) {
      const int share = std::max(minModelTriangles(p.kind), int(std::lround(p.share * triangles)));
      const TriMesh mesh = modelMesh(p.kind, share, options.seed + p.seedOffset);
      objects.push_back(
          meshObject(p.id, placedMesh(mesh, modelScale(p.kind, mesh, p.size), p.at, p.rest)));
    }
    camera.position = Vec3(0, 2.2, kDenseHalfSide - 0.1);
    camera.target = Vec3(0, 0.6, 0);
    camera.fovYDeg = 75;
  }
  if (options.smooth)
    for (Object& object : objects)
      if (!object.isStatic && object.id.rfind("table_", 0) != 0)
        object.normals = smoothCornerNormals(object.vertices, object.faces);
  return Scene(std::move(lights), std::move(materials), std::move(objects), camera);
}

}  // namespace penumbra
