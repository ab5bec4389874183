// The full build against the independent exact reference (DESIGN.md invariants
// 1 and 2) over seeded generated scenes: every DM vertex's value and class equal
// the brute-force reference, and the triangles tile every receiving face.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "core/engine/engine.h"
#include "core/reference/exact_irradiance.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"

namespace penumbra {
namespace {

struct Mismatches {
  size_t vertices = 0, valueErrors = 0, classErrors = 0;
};

// Invariant 1 at the tree vertices (the values the engine computed at points).
Mismatches compareVertices(const Engine& engine, const ExactReference& reference, double peak) {
  Mismatches m;
  for (const Engine::Receiver& receiver : engine.receivers()) {
    for (VertexId v : receiver.tree.vertices()) {
      const Vec3 p = receiver.frame.to3D(receiver.tree.position(v));
      const PointIrradiance truth = reference.evaluate(p, receiver.frame.normal);
      const VertexIrradiance& value = engine.value(receiver, v);
      ++m.vertices;
      for (int c = 0; c < 3; ++c) {
        if (std::abs(value.irradiance[c] - truth.irradiance[c]) >
            1e-9 * std::abs(truth.irradiance[c]) + 1e-12 * peak) {
          if (m.valueErrors++ < 5)
            ADD_FAILURE() << "face " << receiver.face.object << "/" << receiver.face.face << " vertex "
                          << v.index << ": engine " << value.irradiance[c] << " reference "
                          << truth.irradiance[c];
          break;
        }
      }
      // A vertex exactly on a shadow boundary may take either neighbouring class:
      // only a disagreement that the values themselves contradict counts.
      if (value.lightClass != truth.lightClass) {
        const bool boundary = (value.lightClass == LightClass::Penumbra || truth.lightClass == LightClass::Penumbra);
        if (!boundary && m.classErrors++ < 5)
          ADD_FAILURE() << "class " << toString(value.lightClass) << " vs " << toString(truth.lightClass);
      }
    }
  }
  return m;
}

// Invariant 1 at every output vertex (lattice points included): a location that
// repeats (one copy per side of a value jump, dark copies in umbra cells) must have
// a copy equal to the reference at that point, or else (a contact on the face's own
// boundary, seen from one side only) every copy must be the limit from its side:
// the reference just inside a triangle that uses it.
size_t compareMeshVertices(const Scene& scene, const Mesh& mesh, const ExactReference& reference,
                           double peak) {
  const double onPlane = scene.tolerance().onPlane();
  size_t errors = 0;
  for (const ReceiverMesh& r : mesh.receivers) {
    std::map<std::tuple<double, double, double>, std::vector<size_t>> copies;
    for (size_t i = 0; i < r.positions.size(); ++i)
      copies[{r.positions[i].x, r.positions[i].y, r.positions[i].z}].push_back(i);
    std::vector<size_t> triangleOf(r.positions.size());
    for (size_t t = 0; t < r.triangles.size(); ++t)
      for (uint32_t i : r.triangles[t]) triangleOf[i] = t;
    auto limitMatches = [&](size_t i) {
      const auto& t = r.triangles[triangleOf[i]];
      const Vec3 inside = (r.positions[t[0]] + r.positions[t[1]] + r.positions[t[2]]) / 3.0;
      // The shortest step towards the triangle's centre (within a factor 2, at most
      // the centre itself: a sliver cell along a contact can be thinner than the
      // band a tenth of the way in) that clears every face plane through the vertex
      // (so those faces count as blockers, as in the limit).
      const Vec3 p = r.positions[i];
      for (double t = 1.0 / 1024; t <= 1; t *= 2) {
        const Vec3 q = p + t * (inside - p);
        // (Planes holding the receiver's plane contain p and q alike: skip them.)
        const bool clear = std::all_of(scene.faces().begin(), scene.faces().end(), [&](const Face& f) {
          return std::abs(f.plane.signedDistance(p)) > onPlane ||
                 std::abs(glm::dot(f.plane.normal, r.normal)) > 1 - 1e-12 ||
                 std::abs(f.plane.signedDistance(q)) > 2 * onPlane;
        });
        if (clear)
          return std::abs(r.irradiance[i].x - reference.evaluate(q, r.normal).irradiance.x) <= 1e-3 * peak;
      }
      return false;
    };
    for (const auto& [at, indices] : copies) {
      const PointIrradiance truth = reference.evaluate(r.positions[indices[0]], r.normal);
      bool matched = false;
      for (size_t i : indices)
        matched |= std::abs(r.irradiance[i].x - truth.irradiance.x) <=
                   1e-9 * std::abs(truth.irradiance.x) + 1e-12 * peak;
      if (!matched) matched = std::all_of(indices.begin(), indices.end(), limitMatches);
      if (!matched && errors++ < 5)
        ADD_FAILURE() << "mesh vertex of face " << r.face.object << "/" << r.face.face << ": "
                      << r.irradiance[indices[0]].x << " (" << indices.size() << " copies), reference "
                      << truth.irradiance.x;
    }
  }
  return errors;
}

// Invariant 2: triangles tile each receiving face.
void expectCover(const Scene& scene, const Mesh& mesh) {
  for (const ReceiverMesh& r : mesh.receivers) {
    const Face* face = nullptr;
    for (const Face& f : scene.faces())
      if (f.id == r.face) face = &f;
    ASSERT_NE(face, nullptr);
    double sum = 0;
    for (const auto& t : r.triangles) {
      const Vec3 n = glm::cross(r.positions[t[1]] - r.positions[t[0]], r.positions[t[2]] - r.positions[t[0]]);
      EXPECT_GT(glm::dot(n, r.normal), 0) << "triangle not counter-clockwise or degenerate";
      sum += 0.5 * glm::length(n);
    }
    EXPECT_NEAR(sum, face->area, 1e-9 * face->area);
  }
}

double peakIrradiance(const Engine& engine) {
  double peak = 0;
  for (const auto& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, engine.value(r, v).irradiance.x);
  return peak;
}

TEST(EngineBuild, DemoScenesMatchReference) {
  for (const char* name : {"cornell", "office", "cubes15"}) {
    SCOPED_TRACE(name);
    const Scene scene = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name + ".scene.json");
    Engine engine(scene);
    engine.validate();
    const ExactReference reference(engine.scene());
    const Mismatches m = compareVertices(engine, reference, peakIrradiance(engine));
    std::printf("%s: %zu vertices, %zu value errors, %zu class errors\n", name, m.vertices, m.valueErrors, m.classErrors);
    EXPECT_EQ(m.valueErrors, 0u);
    EXPECT_EQ(m.classErrors, 0u);
    expectCover(engine.scene(), engine.mesh());
  }
}

TEST(EngineBuild, GeneratedScenesMatchReference) {
  size_t scenes = 0, vertices = 0, valueErrors = 0, classErrors = 0;
  for (uint64_t seed = 1; seed <= 200; ++seed) {
    const CubesSceneOptions options = mixedCubesOptions(seed);
    SCOPED_TRACE(seed);
    Engine engine(makeCubesScene(options));
    engine.validate();
    const ExactReference reference(engine.scene());
    const Mismatches m = compareVertices(engine, reference, peakIrradiance(engine));
    ++scenes;
    vertices += m.vertices;
    valueErrors += m.valueErrors;
    classErrors += m.classErrors;
    expectCover(engine.scene(), engine.mesh());
  }
  std::printf("%zu scenes, %zu vertices, %zu value errors, %zu class errors\n", scenes, vertices, valueErrors, classErrors);
  EXPECT_EQ(valueErrors, 0u);
  EXPECT_EQ(classErrors, 0u);
}

// Every output vertex, lattice points and per-side copies included.
TEST(EngineBuild, MeshVerticesMatchReferenceOrSideLimit) {
  size_t errors = 0, scenes = 0;
  auto check = [&](const Scene& scene) {
    Engine engine(scene);
    const ExactReference reference(engine.scene());
    errors += compareMeshVertices(engine.scene(), engine.mesh(), reference, peakIrradiance(engine));
    ++scenes;
  };
  for (const char* name : {"cornell", "office", "cubes15"})
    check(protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/" + name + ".scene.json"));
  for (uint64_t seed = 1; seed <= 200; ++seed) check(makeCubesScene(mixedCubesOptions(seed)));
  std::printf("%zu scenes, %zu mesh vertices off\n", scenes, errors);
  EXPECT_EQ(errors, 0u);
}

}  // namespace
}  // namespace penumbra
