// The lattice display (core/mesh/lattice_mesh_memo.h, lattice_display_rule.h): which receivers
// are meshed from their lattice squares, and that such a mesh keeps the tolerance against the
// exact reference (ExactReference, no code shared with the engine), holds the exact value at its
// vertices, follows edits incrementally bit for bit as a fresh mesh, and takes a new radiance
// without lighting a square again.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>

#include "core/engine/engine.h"
#include "core/raycast/mesh_lookup.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/dense_scene.h"
#include "scenegen/scene_parts.h"
#include "scenegen/model_scene.h"
#include "tests/core/engine/display_bound.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra {
namespace lattice_display_test {  // its own names: the unity build joins test files
namespace {

using testing::BoundCheck;
using testing::checkBound;
using testing::expectSameAsAFreshMesh;
using testing::pointsOnFace;

constexpr double kTolerance = EngineSettings::kRecommendedMeshTolerance;
constexpr double kSlack = 2;  // as DisplayRefinement's: 1 % of the local level at the default 0.5 %

Scene modelScene(ModelKind kind, int triangles, bool rest, uint64_t seed = 1) {
  ModelSceneOptions options;
  options.kind = kind;
  options.triangles = triangles;
  options.rest = rest;
  options.seed = seed;
  return makeModelScene(options);
}

// Settings that put the lattice display on small models' floors (a few hundred DM vertices in
// a square): the product's rule, with a lower bar.
EngineSettings latticeAbove(uint32_t above) {
  EngineSettings settings;
  settings.meshTolerance = kTolerance;
  settings.meshLatticeAbove = above;
  return settings;
}

const Face& floorOf(const Scene& scene) {
  const auto index = std::find_if(scene.objects().begin(), scene.objects().end(),
                                  [](const Object& o) { return o.id == "floor"; }) - scene.objects().begin();
  return scene.facesOfObject(scene.handleOf(size_t(index))).front();
}

const ReceiverMesh& partOf(const Mesh& mesh, FaceId face) {
  const auto it = std::find_if(mesh.receivers.begin(), mesh.receivers.end(),
                               [&](const ReceiverMesh& r) { return r.face == face; });
  if (it == mesh.receivers.end()) throw std::runtime_error("no display mesh on the face");
  return *it;
}

// Every seventh vertex of a receiver's display mesh carries the exact value at its point (a
// vertex repeated per side of a contact line is not: none on a floor meshed from squares).
void expectMeshVerticesExact(const Scene& scene, const ReceiverMesh& part, const Face& face) {
  const ExactReference reference(scene);
  double peak = 0;
  for (const Vec3& e : part.irradiance) peak = std::max(peak, e.x);
  size_t off = 0;
  for (size_t v = 0; v < part.positions.size(); v += 7) {
    const Vec3 exact = reference.evaluate(part.positions[v], face.plane.normal).irradiance;
    if (std::abs(exact.x - part.irradiance[v].x) > 1e-9 * peak && off++ < 3)
      ADD_FAILURE() << "vertex " << v << ": " << part.irradiance[v].x << " vs exact " << exact.x;
  }
}

// Under a floating 1,000-triangle teapot the product's own rule (default settings) meshes the
// floor from its squares; resting on the floor (contact lines), it keeps the floor's cells, as
// do the model's own faces and a dense room of boxes, even with the density bar lowered (its
// cells have lists of their own).
TEST(LatticeDisplay, TheRuleTakesFloorsUnderFloatingModelsOnly) {
  {
    const Scene scene = modelScene(ModelKind::Teapot, 1000, false);
    Engine engine(scene, EngineSettings{});
    engine.mesh();
    EXPECT_TRUE(engine.meshedFromLattice(floorOf(scene).id));
    const auto teapot = std::find_if(scene.objects().begin(), scene.objects().end(),
                                     [](const Object& o) { return o.id == "teapot"; }) - scene.objects().begin();
    for (const Face& face : scene.facesOfObject(scene.handleOf(size_t(teapot))))
      EXPECT_FALSE(engine.meshedFromLattice(face.id)) << "a face of the model";
  }
  {
    const Scene scene = modelScene(ModelKind::Teapot, 1000, true);
    Engine engine(scene, latticeAbove(20));
    engine.mesh();
    EXPECT_FALSE(engine.meshedFromLattice(floorOf(scene).id)) << "resting: contact on the floor";
  }
  {
    const Scene scene = makeDenseScene(DenseSceneOptions{150, 1});
    for (const uint32_t above : {EngineSettings::kDefaultLatticeAbove, 20u}) {
      Engine engine(scene, latticeAbove(above));
      engine.mesh();
      for (const Face& face : scene.faces()) EXPECT_FALSE(engine.meshedFromLattice(face.id)) << "bar " << above;
    }
  }
}

// Floating models of every kind, their floors meshed from squares: random floor points keep
// the bound, and every vertex of the floor's mesh carries the exact value at its point.
TEST(LatticeDisplay, FloorsOfFloatingModelsKeepTheToleranceAndExactVertices) {
  const ModelKind kinds[] = {ModelKind::Teapot, ModelKind::TorusKnot, ModelKind::Blob, ModelKind::Bowl};
  for (size_t k = 0; k < std::size(kinds); ++k) {
    SCOPED_TRACE("model " + std::to_string(k));
    const Scene scene = modelScene(kinds[k], 400, false, k + 1);
    Engine engine(scene, latticeAbove(20));
    const Mesh mesh = engine.mesh();
    const Face& floor = floorOf(scene);
    ASSERT_TRUE(engine.meshedFromLattice(floor.id));
    const BoundCheck check = checkBound(engine, mesh, kTolerance, kSlack, pointsOnFace(floor, 600, 7 + k));
    EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ")";
    expectMeshVerticesExact(scene, partOf(mesh, floor.id), floor);
  }
}

// Unrefined cells (meshTolerance 0, what `serve` keeps by default) still put the floor under a
// floating model on its squares, refined to the recommended tolerance: bare squares would be far
// coarser than the cells, and the cells' fans need every DM vertex lit (the floor under a 4,500-
// triangle knot: 196 k of its 203 k, 2.5x the served build). The mesh claims no bound (0).
TEST(LatticeDisplay, UnrefinedCellsStillRefineTheFloorsSquares) {
  const Scene scene = modelScene(ModelKind::TorusKnot, 1000, false, 3);
  EngineSettings settings;
  settings.meshTolerance = 0;
  Engine engine(scene, settings);
  const Mesh mesh = engine.mesh();
  EXPECT_EQ(mesh.tolerance, 0.0);
  const Face& floor = floorOf(scene);
  ASSERT_TRUE(engine.meshedFromLattice(floor.id));
  const BoundCheck check = checkBound(engine, mesh, kTolerance, kSlack, pointsOnFace(floor, 600, 11));
  EXPECT_EQ(check.over, 0u) << check.first << " (worst " << check.worst << ")";
  expectMeshVerticesExact(scene, partOf(mesh, floor.id), floor);
  EXPECT_GT(engine.stats().latticeVertices, engine.stats().vertices / 2) << "the floor's DM vertices are not lit";
}

// A floating knot dragged and turned in steps (each a whole rebuild: the knot is most of the
// scene), then a small box added floating over a corner of the floor and moved there (each an
// incremental frame): after each the floor is meshed from squares, the kept mesh equals a fresh
// one bit for bit and keeps the bound, and the box's frames light only some squares again. A
// radiance change then lights no square and scales the floor's values.
TEST(LatticeDisplay, EditsEqualAFreshMeshAndRadianceLightsNoSquare) {
  const Scene scene = modelScene(ModelKind::TorusKnot, 400, false, 3);
  const Object& model = scene.objects().back();
  const Face& floor = floorOf(scene);
  Engine engine(scene, latticeAbove(20));
  engine.mesh();
  const auto check = [&](uint64_t seed) {
    const Mesh kept = engine.mesh();
    ASSERT_TRUE(engine.meshedFromLattice(floor.id));
    const BoundCheck bound = checkBound(engine, kept, kTolerance, kSlack, pointsOnFace(floor, 300, seed));
    EXPECT_EQ(bound.over, 0u) << bound.first << " (worst " << bound.worst << ")";
    expectSameAsAFreshMesh(engine, kept);
  };
  for (int step = 1; step <= 2; ++step) {
    SCOPED_TRACE("knot step " + std::to_string(step));
    Edit move;
    move.op = Edit::Op::Move;
    move.id = model.id;
    move.transform = model.transform;
    move.transform.translate += Vec3(0.04 * step, 0, -0.03 * step);
    move.transform.rotateDeg.y += 4.0 * step;
    engine.apply(Frame{{move}});
    check(50 + uint64_t(step));
  }
  Edit add;
  add.op = Edit::Op::Add;
  add.object.id = "box";
  add.object.material = model.material;
  addBox(add.object, Vec3(-2.6, 0.4, -2.6), Vec3(-2.3, 0.6, -2.3));
  for (int step = 0; step <= 2; ++step) {
    SCOPED_TRACE("box step " + std::to_string(step));
    Edit edit = add;
    if (step > 0) {
      edit = Edit{};
      edit.op = Edit::Op::Move;
      edit.id = "box";
      edit.transform.translate = Vec3(0.05 * step, 0, 0.04 * step);
    }
    const FrameResult result = engine.apply(Frame{{edit}});
    EXPECT_FALSE(result.fullRebuild);
    engine.mesh();
    const auto counters = engine.lastMeshCounters();
    EXPECT_GT(counters.cellsLit, 0u);
    EXPECT_GT(counters.cellsReused, counters.cellsLit);
    check(60 + uint64_t(step));
  }
  const Mesh before = engine.mesh();
  Edit brighter;
  brighter.op = Edit::Op::SetLight;
  brighter.id = scene.lights()[0].id;
  brighter.radiance = scene.lights()[0].radiance * 2.0;
  engine.apply(Frame{{brighter}});
  const Mesh after = engine.mesh();
  EXPECT_EQ(engine.lastMeshCounters().cellsLit, 0u);
  const ReceiverMesh &a = partOf(before, floor.id), &b = partOf(after, floor.id);
  ASSERT_EQ(a.positions, b.positions);
  for (size_t v = 0; v < a.irradiance.size(); ++v) EXPECT_NEAR(b.irradiance[v].x, 2 * a.irradiance[v].x, 1e-12 * (1 + a.irradiance[v].x));
}

// Every DM vertex of the floor carries the exact value, kept or (meshed from squares) computed
// when asked; at most three failures are reported.
void expectFloorVerticesExact(const Engine& engine, const Face& floor) {
  const Engine::Receiver* receiver = engine.receiver(floor.id);
  ASSERT_NE(receiver, nullptr);
  const ExactReference reference(engine.scene());
  const std::vector<VertexId> vertices = receiver->tree.vertices();
  size_t off = 0;
  for (size_t i = 0; i < vertices.size(); i += 11) {
    const Vec3 p = receiver->frame.to3D(receiver->tree.position(vertices[i]));
    const double exact = reference.evaluate(p, floor.plane.normal).irradiance.x;
    const double ours = engine.value(*receiver, vertices[i]).irradiance.x;
    if (std::abs(exact - ours) > 1e-9 * std::max(1.0, exact) && off++ < 3)
      ADD_FAILURE() << "DM vertex " << vertices[i].index << ": " << ours << " vs exact " << exact;
  }
}

// A floor meshed from squares keeps no vertex values (the build counts them) yet answers each
// exactly; a box set down on it in an incremental frame (contact) gives the floor its cells
// back, every vertex lit; taking the box away puts it on squares again. After each frame the
// kept mesh equals a fresh one and the engine equals one built afresh for its scene.
TEST(LatticeDisplay, FlippingBetweenSquaresAndCellsKeepsValuesExact) {
  const Scene scene = modelScene(ModelKind::TorusKnot, 400, false, 3);
  const Face& floor = floorOf(scene);
  Engine engine(scene, latticeAbove(20));
  engine.mesh();
  ASSERT_TRUE(engine.meshedFromLattice(floor.id));
  EXPECT_GT(engine.stats().latticeVertices, 0u);
  EXPECT_EQ(engine.stats().latticeVertices, engine.receiver(floor.id)->tree.vertexCount());
  expectFloorVerticesExact(engine, floor);
  Edit add;
  add.op = Edit::Op::Add;
  add.object.id = "box";
  add.object.material = scene.objects().back().material;
  addBox(add.object, Vec3(-2.6, 0, -2.6), Vec3(-2.3, 0.2, -2.3));
  Edit remove;
  remove.op = Edit::Op::Remove;
  remove.id = "box";
  const std::pair<Edit, bool> steps[] = {{add, false}, {remove, true}};
  for (const auto& [edit, squares] : steps) {
    SCOPED_TRACE(squares ? "box removed" : "box added");
    const FrameResult result = engine.apply(Frame{{edit}});
    EXPECT_FALSE(result.fullRebuild);
    const Mesh kept = engine.mesh();
    EXPECT_EQ(engine.meshedFromLattice(floor.id), squares);
    expectSameAsAFreshMesh(engine, kept);
    expectFloorVerticesExact(engine, floor);
    if (squares) expectMeshVerticesExact(engine.scene(), partOf(kept, floor.id), floor);
    const BoundCheck bound = checkBound(engine, kept, kTolerance, kSlack, pointsOnFace(floor, 300, 70));
    EXPECT_EQ(bound.over, 0u) << bound.first << " (worst " << bound.worst << ")";
    Engine fresh(engine.scene(), latticeAbove(20));
    fresh.mesh();
    EXPECT_EQ(fresh.meshedFromLattice(floor.id), squares);
    const testing::EngineDiff diff = testing::compareEngines(engine, fresh, testing::peakIrradiance(fresh), 100, 9);
    EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
  }
}

}  // namespace
}  // namespace lattice_display_test
}  // namespace penumbra
