// A closed convex object cast as one occluder (core/shadow/object_shadow.h): when it may,
// its penumbra holds every face's and its umbra every face's umbra; the engine then matches
// the exact reference at every vertex on seeded random ellipsoids and boxes with fewer
// vertices than face by face, and edits that switch an object between whole and face by
// face (resting on the floor) equal a rebuild.
#include "core/shadow/object_shadow.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <string>

#include "core/engine/engine.h"
#include "core/scene/convex_solid.h"
#include "core/scene/mesh_topology.h"
#include "core/shadow/cast_shadow.h"
#include "scenegen/dense_scene.h"
#include "scenegen/model_scene.h"
#include "scenegen/sphere_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/reference_check.h"

namespace penumbra {
namespace {

// A UV sphere of `faces` faces, scaled by `scale` (an ellipsoid: still closed convex) and
// turned, at `centre` of the dense room.
Scene ellipsoidScene(int faces, double radius, const Vec3& centre, const Vec3& scale, const Vec3& turn) {
  const Scene sphere = makeSphereScene({.faces = faces, .radius = radius, .centre = Vec3(0.0, 1.5, 0.0)});
  std::vector<Object> objects = sphere.objects();
  for (Object& object : objects)
    if (object.id == "sphere") {
      // The sphere's vertices are placed at its centre in world space: move them to the
      // origin so the transform scales and turns about the centre.
      for (Vec3& v : object.vertices) v -= Vec3(0.0, 1.5, 0.0);
      object.transform.translate = centre;
      object.transform.scale = scale;
      object.transform.rotateDeg = turn;
    }
  return Scene(sphere.lights(), sphere.materials(), objects, sphere.camera());
}

Scene randomEllipsoid(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int faces[] = {24, 60, 128, 200};
  const double radius = 0.15 + 0.2 * unit(rng);
  const Vec3 scale(0.6 + 0.8 * unit(rng), 0.6 + 0.8 * unit(rng), 0.6 + 0.8 * unit(rng));
  const Vec3 centre(-1.5 + 3.0 * unit(rng), 0.5 + 1.2 * unit(rng), -1.5 + 3.0 * unit(rng));
  const Vec3 turn(360 * unit(rng), 360 * unit(rng), 360 * unit(rng));
  return ellipsoidScene(faces[rng() % 4], radius, centre, scale, turn);
}

const Face& faceNamed(const Scene& scene, const std::string& object) {
  return scene.facesOfObject(scene.handleOf(*scene.findObject(object))).front();
}

size_t dmVertexCount(const Engine& engine) {
  size_t n = 0;
  for (const Engine::Receiver& r : engine.receivers()) n += r.tree.vertices().size();
  return n;
}

size_t wholeEntries(const Engine& engine) {
  size_t n = 0;
  for (const Engine::Receiver& r : engine.receivers())
    for (CellId c : r.tree.cells())
      for (const OccluderEntry& e : r.tree.occluders(c)) n += isWholeObject(e.face);
  return n;
}

bool insideWithin(const Polygon2& polygon, const Vec2& p, double eps) {
  for (size_t i = 0; i < polygon.size(); ++i)
    if (lineDistance(polygon[i], polygon[(i + 1) % polygon.size()], p) < -eps) return false;
  return true;
}

TEST(ObjectShadow, CastsWholeOnlyOffTheReceiverAndInFrontOfTheLight) {
  const Scene floating = makeSphereScene({.faces = 72, .radius = 0.3, .centre = Vec3(0.2, 1.0, 0.1)});
  const uint32_t sphere = floating.handleOf(*floating.findObject("sphere"));
  EXPECT_TRUE(castsAsOneOccluder(floating, 0, sphere, faceNamed(floating, "floor")));
  // Resting on the floor (its pole on it): face by face there, whole on a wall.
  const Scene resting = ellipsoidScene(72, 0.3, Vec3(0.2, 0.3, 0.1), Vec3(1.0), Vec3(0.0));
  EXPECT_FALSE(castsAsOneOccluder(resting, 0, sphere, faceNamed(resting, "floor")));
  EXPECT_TRUE(castsAsOneOccluder(resting, 0, sphere, faceNamed(resting, "wall_n")));
  // A box is closed convex too; a room wall is not an object that can cast whole.
  const Scene dense = makeDenseScene({.boxes = 5, .seed = 3});
  EXPECT_FALSE(castsAsOneOccluder(dense, 0, faceNamed(dense, "floor").id.object, faceNamed(dense, "ceiling")));
}

// Seeded: the whole object's regions on the floor hold each face's (penumbra: a superset
// of what any face shadows; umbra: where one face hides the light, the object does).
TEST(ObjectShadow, RegionsHoldEveryFacesRegions) {
  std::mt19937_64 rng(7);
  size_t checkedFaces = 0, trialsWithUmbra = 0;
  for (int trial = 0; trial < 12; ++trial) {
    const Scene scene = randomEllipsoid(rng);
    const uint32_t handle = scene.handleOf(*scene.findObject("sphere"));
    const Face& floor = faceNamed(scene, "floor");
    ASSERT_TRUE(castsAsOneOccluder(scene, 0, handle, floor)) << "trial " << trial;
    const PlaneFrame frame = PlaneFrame::onPlane(floor.plane, floor.polygon[0]);
    const auto whole = castObjectShadow(scene, 0, handle, floor, frame);
    ASSERT_TRUE(whole) << "trial " << trial;
    EXPECT_EQ(whole->occluder, wholeObject(handle));
    trialsWithUmbra += !whole->umbra.empty();
    const double eps = 10 * scene.tolerance().length();
    for (const Face& face : scene.facesOfObject(handle)) {
      const auto one = castShadow(scene, 0, face, floor, frame, false);
      if (!one) continue;
      ++checkedFaces;
      for (const Vec2& p : one->penumbra)
        EXPECT_TRUE(insideWithin(whole->penumbra, p, eps)) << "trial " << trial << " face " << face.id.face;
      // No umbra of the object: none of a face either.
      if (whole->umbra.empty()) EXPECT_TRUE(one->umbra.empty()) << "trial " << trial << " face " << face.id.face;
      for (const Vec2& p : one->umbra)
        EXPECT_TRUE(insideWithin(whole->umbra, p, eps)) << "trial " << trial << " face " << face.id.face;
    }
  }
  EXPECT_GT(checkedFaces, 200u);
  EXPECT_GE(trialsWithUmbra, 3u);
}

// A mesh past 65,535 edges (element indices were 16 bits: such a mesh cast face by face)
// casts whole, and every segment's elements are the ones that make it: its two ends lie in
// the plane of its light vertex and occluder edge (VE) or of its light edge and occluder
// vertex (EV). A truncated index names another edge or vertex, off that plane.
TEST(ObjectShadow, AMeshPastSixteenBitElementIndicesCastsWholeWithItsOwnElements) {
  const Scene scene = makeModelScene({.kind = ModelKind::TorusKnot, .triangles = 50000});
  const uint32_t handle = scene.handleOf(*scene.findObject("torus_knot"));
  const MeshTopology* mesh = scene.meshTopology(handle);
  ASSERT_NE(mesh, nullptr);
  ASSERT_GT(mesh->welded.edges.size(), 0xffffu);
  const Face& floor = faceNamed(scene, "floor");
  ASSERT_TRUE(castsAsOneOccluder(scene, 0, handle, floor));
  const PlaneFrame frame = PlaneFrame::onPlane(floor.plane, floor.polygon[0]);
  const auto shadow = castObjectShadow(scene, 0, handle, floor, frame);
  ASSERT_TRUE(shadow);
  const Polygon3& light = scene.lights()[0].polygon;
  const ConvexSolid& w = mesh->welded;
  // Whether both ends of s lie within 1e-7 of the plane through x, y, z.
  auto onPlaneOf = [&](const CriticalSegment& s, const Vec3& x, const Vec3& y, const Vec3& z) {
    const Vec3 normal = glm::normalize(glm::cross(y - x, z - x));
    return std::abs(glm::dot(normal, frame.to3D(s.a) - x)) < 1e-7 &&
           std::abs(glm::dot(normal, frame.to3D(s.b) - x)) < 1e-7;
  };
  size_t checked = 0, pastSixteenBits = 0;
  for (const CriticalSegment& s : shadow->segments) {
    if (s.kind == SegmentKind::Contact) continue;
    const uint32_t o = s.occluderElement.index;
    bool found = false;
    if (s.occluderElement.kind == ElementRef::Kind::Edge) {
      ASSERT_LT(o, w.edges.size());
      for (const Vec3& corner : light)
        found = found || onPlaneOf(s, corner, w.vertices[w.edges[o].first], w.vertices[w.edges[o].second]);
    } else {
      ASSERT_LT(o, w.vertices.size());
      for (size_t i = 0; i < light.size(); ++i)
        found = found || onPlaneOf(s, light[i], light[(i + 1) % light.size()], w.vertices[o]);
    }
    EXPECT_TRUE(found) << "segment " << checked << ": occluder element " << o;
    ++checked;
    pastSixteenBits += o > 0xffffu;
  }
  EXPECT_GT(checked, 100u);
  EXPECT_GT(pastSixteenBits, 0u);
}

void expectExactAndSmaller(const Scene& scene, const std::string& label) {
  EngineSettings faces;
  faces.closedObjectsAsOne = false;
  Engine whole(scene);
  const Engine byFace(scene, faces);
  whole.validate();
  const testing::ReferenceCheck c = testing::checkAgainstReference(whole, label);
  std::printf("%s: %zu DM vertices face by face, %zu whole (%zu whole-object list entries)\n", label.c_str(),
              dmVertexCount(byFace), c.vertices, wholeEntries(whole));
  EXPECT_EQ(c.valueErrors, 0u) << label;
  EXPECT_EQ(c.classErrors, 0u) << label;
  EXPECT_GT(wholeEntries(whole), 0u) << label;
  EXPECT_LT(c.vertices, dmVertexCount(byFace)) << label;
}

TEST(ObjectShadow, RandomEllipsoidsMatchReferenceWithFewerVertices) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 4; ++trial) expectExactAndSmaller(randomEllipsoid(rng), "ellipsoid " + std::to_string(trial));
}

TEST(ObjectShadow, DenseBoxesMatchReferenceWithFewerVertices) {
  for (uint64_t seed = 4; seed <= 5; ++seed)
    expectExactAndSmaller(makeDenseScene({.boxes = 20, .seed = seed}), "dense 20 seed " + std::to_string(seed));
}

// Moves that take the ellipsoid from floating (whole on the floor) to resting on it (face
// by face there, contact lines) and back, each equal to a rebuild.
TEST(ObjectShadow, EditsSwitchingWholeAndFaceByFaceEqualRebuild) {
  Engine engine(ellipsoidScene(60, 0.3, Vec3(0.3, 1.1, -0.2), Vec3(1.2, 0.7, 0.9), Vec3(20, 30, 0)));
  const uint32_t handle = engine.scene().handleOf(*engine.scene().findObject("sphere"));
  const double heights[] = {0.21, 0.9, 0.2100001, 1.4};
  int f = 0;
  bool sawFaceByFace = false, sawWhole = false;
  for (double y : heights) {
    Edit move;
    move.op = Edit::Op::Move;
    move.id = "sphere";
    move.transform = engine.scene().object(handle).transform;
    move.transform.translate = Vec3(0.3 - 0.2 * f, y, -0.2 + 0.1 * f);
    move.transform.rotateDeg = Vec3(0, 0, 0);
    const FrameResult result = engine.apply(Frame{{move}});
    EXPECT_FALSE(result.fullRebuild);
    EXPECT_EQ(result.treeRebuilds, 0u);
    engine.validate();
    const bool whole = castsAsOneOccluder(engine.scene(), 0, handle, faceNamed(engine.scene(), "floor"));
    (whole ? sawWhole : sawFaceByFace) = true;
    const Engine rebuilt(engine.scene());
    const testing::EngineDiff diff =
        testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 200, uint64_t(f));
    EXPECT_EQ(diff.errors(), 0u) << "frame " << f << ": " << diff.firstProblem;
    ++f;
  }
  EXPECT_TRUE(sawWhole);
  EXPECT_TRUE(sawFaceByFace);
  const testing::ReferenceCheck c = testing::checkAgainstReference(engine, "ellipsoid after the moves");
  EXPECT_EQ(c.valueErrors, 0u);
  EXPECT_EQ(c.classErrors, 0u);
}

}  // namespace
}  // namespace penumbra
