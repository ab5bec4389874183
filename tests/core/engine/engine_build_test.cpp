// The full build against the independent exact reference (DESIGN.md invariants
// 1 and 2) over seeded generated scenes: every DM vertex's value and class equal
// the brute-force reference, and the triangles tile every receiving face.
#include <gtest/gtest.h>

#include <cmath>

#include "bench/lib/cubes_scene.h"
#include "core/engine/engine.h"
#include "core/reference/exact_irradiance.h"
#include "protocol/scene_json.h"

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
      const VertexIrradiance& value = receiver.values[v.index];
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
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, r.values[v.index].irradiance.x);
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

}  // namespace
}  // namespace penumbra
