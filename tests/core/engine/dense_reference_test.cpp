// The full build on dense rooms (boxes floating at random, dozens of faces covering
// a vertex) against the independent exact reference: every DM vertex's value equals
// the brute-force reference at 1e-9 relative, and the triangles tile every receiver.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "bench/lib/dense_scene.h"
#include "core/engine/engine.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra {
namespace {

struct DenseCheck {
  size_t vertices = 0, valueErrors = 0, classErrors = 0;
};

DenseCheck checkDenseRoom(int boxes, uint64_t seed) {
  Engine engine(makeDenseScene({.boxes = boxes, .seed = seed}));
  const Mesh& mesh = engine.mesh();
  const ExactReference reference(engine.scene());
  double peak = 0;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, r.values[v.index].irradiance.x);
  DenseCheck out;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) {
      const Vec3 p = r.frame.to3D(r.tree.position(v));
      const PointIrradiance truth = reference.evaluate(p, r.frame.normal);
      const VertexIrradiance& value = r.values[v.index];
      ++out.vertices;
      const double error = std::abs(value.irradiance.x - truth.irradiance.x);
      if (error > 1e-9 * std::abs(truth.irradiance.x) + 1e-12 * peak && out.valueErrors++ < 5)
        ADD_FAILURE() << "N " << boxes << " seed " << seed << " face " << r.face.object << "/"
                      << r.face.face << " vertex " << v.index << ": engine " << value.irradiance.x
                      << " reference " << truth.irradiance.x;
      // A vertex on a shadow boundary may take either neighbouring class.
      const bool boundary = value.lightClass == LightClass::Penumbra || truth.lightClass == LightClass::Penumbra;
      if (value.lightClass != truth.lightClass && !boundary && out.classErrors++ < 5)
        ADD_FAILURE() << "class " << toString(value.lightClass) << " vs " << toString(truth.lightClass);
    }
  // The triangles tile every receiving face.
  for (const ReceiverMesh& r : mesh.receivers) {
    double sum = 0, faceArea = 0;
    for (const auto& t : r.triangles)
      sum += 0.5 * glm::length(glm::cross(r.positions[t[1]] - r.positions[t[0]], r.positions[t[2]] - r.positions[t[0]]));
    for (const Face& f : engine.scene().faces())
      if (f.id == r.face) faceArea = f.area;
    EXPECT_NEAR(sum, faceArea, 1e-9 * faceArea);
  }
  std::printf("dense N=%d seed %llu: %zu vertices, %zu value errors, %zu class errors\n", boxes,
              (unsigned long long)seed, out.vertices, out.valueErrors, out.classErrors);
  return out;
}

TEST(DenseReference, SmallRoomsEverySeed) {
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    const DenseCheck c = checkDenseRoom(int(10 + 5 * seed), seed);
    EXPECT_EQ(c.valueErrors, 0u);
    EXPECT_EQ(c.classErrors, 0u);
  }
}

TEST(DenseReference, Dense150) {
  const DenseCheck c = checkDenseRoom(150, 1);
  EXPECT_EQ(c.valueErrors, 0u);
  EXPECT_EQ(c.classErrors, 0u);
}

}  // namespace
}  // namespace penumbra
