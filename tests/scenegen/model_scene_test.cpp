// Model scenes (scenegen/model_scene.h) through the project's own scene validation (the
// scene JSON reader, which rebuilds the Scene and refuses degenerate or too thin faces):
// every model floating and resting, at a few sizes; resting ones touch the floor (min y = 0
// exactly), floating ones do not; every face at least the scene's minimum width; the
// furnished room's objects apart from each other inside the room below the light, its
// tables' models touching their tops, ~100 k triangles; bad requests refused.
#include "scenegen/model_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/geom/polygon.h"
#include "protocol/scene_json.h"
#include "scenegen/dense_scene.h"

namespace penumbra {
namespace {

bool isRoom(const Object& object) { return object.isStatic; }

// The scene as written and read back by the validating reader; the same faces.
Scene validated(const Scene& scene) {
  Scene back = protocol::sceneFromJson(protocol::sceneToJson(scene));
  EXPECT_EQ(back.faces().size(), scene.faces().size());
  return back;
}

double thinnest(const Scene& scene) {
  double out = INFINITY;
  for (const Face& face : scene.faces()) out = std::min(out, width(face.polygon));
  return out;
}

TEST(ModelScene, EveryModelFloatingAndRestingValidates) {
  for (ModelKind kind :
       {ModelKind::Teapot, ModelKind::TorusKnot, ModelKind::Blob, ModelKind::Bowl, ModelKind::Scan})
    for (int asked : {300, 1000, 6000})
      for (bool rest : {false, true}) {
        if (asked < minModelTriangles(kind)) continue;
        const std::string what = std::string(modelKindName(kind)) + " " + std::to_string(asked) +
                                 (rest ? " resting" : " floating");
        const Scene scene =
            validated(makeModelScene({.kind = kind, .triangles = asked, .rest = rest, .seed = 5}));
        ASSERT_EQ(scene.objects().size(), 7u) << what;
        const Object& model = scene.objects().back();
        EXPECT_FALSE(isRoom(model)) << what;
        EXPECT_GE(double(model.faces.size()), 0.75 * asked) << what;
        EXPECT_LE(double(model.faces.size()), 1.25 * asked) << what;
        for (const auto& face : model.faces) EXPECT_EQ(face.size(), 3u) << what;
        EXPECT_GE(thinnest(scene), scene.tolerance().minFaceWidth()) << what;
        const TriMesh mesh = objectMesh(model);
        EXPECT_EQ(meshEdges(mesh).closed(), modelIsClosed(kind)) << what;
        EXPECT_TRUE(meshEdges(mesh).consistent()) << what;
        const MeshBounds bounds = meshBounds(mesh);
        if (rest) {
          EXPECT_EQ(bounds.min.y, 0.0) << what << ": does not touch the floor";
        } else {
          EXPECT_GT(bounds.min.y, 0.3) << what << ": not floating";
          EXPECT_NEAR(bounds.centre().y, 1.0, 1e-12) << what;
        }
        EXPECT_LT(bounds.max.y, kDenseLightY) << what;
        if (kind == ModelKind::Teapot) {
          EXPECT_NEAR(bounds.size().y, 0.6, 1e-12) << what;
        }
      }
}

TEST(ModelScene, ScanAt70kValidates) {
  const Scene scene = validated(makeModelScene({.kind = ModelKind::Scan, .rest = true}));
  const Object& scan = scene.objects().back();
  EXPECT_GE(scan.faces.size(), 52500u);
  EXPECT_LE(scan.faces.size(), 87500u);
  EXPECT_TRUE(meshEdges(objectMesh(scan)).closed());
  EXPECT_EQ(meshBounds(objectMesh(scan)).min.y, 0.0);
  EXPECT_GE(thinnest(scene), scene.tolerance().minFaceWidth());
}

// Intersection of two boxes' interiors is empty when some axis overlaps by ≤ 0.
bool interiorsOverlap(const MeshBounds& a, const MeshBounds& b) {
  for (int axis = 0; axis < 3; ++axis)
    if (std::min(a.max[axis], b.max[axis]) - std::max(a.min[axis], b.min[axis]) <= 0) return false;
  return true;
}

TEST(ModelScene, FurnishedRoomObjectsApartInsideTheRoom) {
  const Scene full = makeModelScene({.kind = ModelKind::Furnished});
  size_t triangles = 0;
  for (const Object& object : full.objects())
    if (!isRoom(object) && object.id.rfind("table_", 0) != 0) triangles += object.faces.size();
  EXPECT_GE(triangles, 75000u);
  EXPECT_LE(triangles, 125000u);

  const Scene scene =
      validated(makeModelScene({.kind = ModelKind::Furnished, .triangles = 20000, .seed = 4}));
  EXPECT_GE(thinnest(scene), scene.tolerance().minFaceWidth());
  std::vector<std::pair<std::string, MeshBounds>> boxes;
  int closed = 0;
  for (const Object& object : scene.objects()) {
    if (isRoom(object)) continue;
    const TriMesh mesh = objectMesh(object);
    const MeshBounds b = meshBounds(mesh);
    EXPECT_GT(b.min.x, -kDenseHalfSide) << object.id;
    EXPECT_LT(b.max.x, kDenseHalfSide) << object.id;
    EXPECT_GT(b.min.z, -kDenseHalfSide) << object.id;
    EXPECT_LT(b.max.z, kDenseHalfSide) << object.id;
    EXPECT_GE(b.min.y, 0.0) << object.id;
    EXPECT_LT(b.max.y, kDenseLightY) << object.id;
    EXPECT_TRUE(meshEdges(mesh).consistent()) << object.id;
    closed += meshEdges(mesh).closed();
    boxes.push_back({object.id, b});
  }
  EXPECT_EQ(boxes.size(), 11u);
  EXPECT_EQ(closed, 2 + 5);  // the tables, two knots, two blobs, the scan
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size(); ++j)
      EXPECT_FALSE(interiorsOverlap(boxes[i].second, boxes[j].second))
          << boxes[i].first << " and " << boxes[j].first;
  auto bounds = [&](const std::string& id) {
    return std::find_if(boxes.begin(), boxes.end(), [&](const auto& b) { return b.first == id; })
        ->second;
  };
  EXPECT_EQ(bounds("teapot_1").min.y, bounds("table_1").max.y);
  EXPECT_EQ(bounds("blob_1").min.y, bounds("table_2").max.y);
  for (const char* id : {"teapot_2", "torus_knot_2", "bowl_1", "scan"})
    EXPECT_EQ(bounds(id).min.y, 0.0) << id;
  for (const char* id : {"blob_2", "torus_knot_1", "bowl_2"})
    EXPECT_GT(bounds(id).min.y, 0.5) << id;
}

TEST(ModelScene, NamesDefaultsAndRefusals) {
  for (const char* name : {"teapot", "torus-knot", "blob", "bowl", "scan", "furnished"}) {
    const auto kind = modelKindFromName(name);
    ASSERT_TRUE(kind) << name;
    EXPECT_STREQ(modelKindName(*kind), name);
  }
  EXPECT_FALSE(modelKindFromName("cow"));
  EXPECT_EQ(defaultModelTriangles(ModelKind::Teapot), 6000);
  EXPECT_EQ(defaultModelTriangles(ModelKind::Scan), 70000);
  EXPECT_EQ(defaultModelTriangles(ModelKind::Furnished), 100000);
  EXPECT_THROW(makeModelScene({.kind = ModelKind::Blob, .triangles = kMinModelTriangles - 1}),
               std::invalid_argument);
  EXPECT_THROW(makeModelScene({.kind = ModelKind::Blob, .triangles = kMaxModelTriangles + 1}),
               std::invalid_argument);
  EXPECT_EQ(minModelTriangles(ModelKind::Scan), 1000);
  EXPECT_THROW(makeModelScene({.kind = ModelKind::Scan, .triangles = 999}), std::invalid_argument);
  EXPECT_THROW(makeModelScene({.kind = ModelKind::Furnished, .triangles = 1000}),
               std::invalid_argument);
  EXPECT_THROW(makeModelScene({.kind = ModelKind::Furnished, .rest = true}), std::invalid_argument);
  EXPECT_THROW(modelMesh(ModelKind::Furnished, 1000, 1), std::invalid_argument);
}

}  // namespace
}  // namespace penumbra
