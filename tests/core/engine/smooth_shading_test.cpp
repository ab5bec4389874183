// Smooth shading (core/scene/shading_normal.h): corner normals follow the object's transform,
// interpolate inside each face and stay in front of it; a mesh with corner normals is shaded
// exactly about the interpolated normal at every DM vertex (against the independent reference,
// which clips its visible pieces rather than the engine's boundary), also after moves.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "core/engine/engine.h"
#include "core/illum/face_lookup.h"
#include "core/scene/shading_normal.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/model_room.h"
#include "tests/core/engine/reference_check.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

using testing::roomWith;

// Each face's own object-space normal at every corner.
std::vector<std::vector<Vec3>> flatCornerNormals(const Object& object) {
  std::vector<std::vector<Vec3>> out;
  for (const auto& face : object.faces) {
    Vec3 newell(0.0);
    for (size_t k = 0; k < face.size(); ++k)
      newell += glm::cross(object.vertices[size_t(face[k])], object.vertices[size_t(face[(k + 1) % face.size()])]);
    out.emplace_back(face.size(), glm::normalize(newell));
  }
  return out;
}

// Smooth normals, each turned by a random angle up to ~25° (kept in front of its face).
Object smoothed(Object object, uint64_t seed) {
  object.normals = smoothCornerNormals(object.vertices, object.faces);
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> jitter(-0.25, 0.25);
  const auto flat = flatCornerNormals(object);
  for (size_t f = 0; f < object.normals.size(); ++f)
    for (Vec3& n : object.normals[f]) {
      Vec3 turned = glm::normalize(n + Vec3(jitter(rng), jitter(rng), jitter(rng)));
      if (glm::dot(turned, flat[f][0]) < 0.2) turned = n;
      n = turned;
    }
  return object;
}

TEST(SmoothShading, CornerNormalsFollowTheTransformAndMirrors) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> angle(-180, 180), scale(0.2, 3.0);
  std::bernoulli_distribution flip(0.5);
  for (int trial = 0; trial < 40; ++trial) {
    Object o = test::bumpySphere("m", {0.1, 1.1, 0.2}, 0.4, 6, 0.3, uint64_t(trial));
    o.normals = flatCornerNormals(o);
    o.transform.rotateDeg = Vec3(angle(rng), angle(rng), angle(rng));
    for (int c = 0; c < 3; ++c) o.transform.scale[c] = scale(rng) * (flip(rng) ? -1 : 1);
    const Scene scene = roomWith({o});
    size_t checked = 0;
    for (const Face& face : scene.faces()) {
      if (face.cornerNormals.empty()) continue;
      for (const Vec3& n : face.cornerNormals) {
        EXPECT_NEAR(glm::dot(n, face.plane.normal), 1.0, 1e-9) << "trial " << trial;
        ++checked;
      }
    }
    EXPECT_EQ(checked, o.faces.size() * 3) << "trial " << trial << ": every face kept its normals";
  }
}

// Distinct normals per corner: each world corner carries the transformed normal of the object
// corner at its position, also where a mirror reversed the face's corners.
TEST(SmoothShading, EachWorldCornerKeepsItsOwnNormal) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> angle(-180, 180), scale(0.3, 2.0);
  for (int trial = 0; trial < 20; ++trial) {
    Object o = test::bumpySphere("m", {0.1, 1.1, 0.2}, 0.4, 6, 0.3, uint64_t(trial));
    o.normals = smoothCornerNormals(o.vertices, o.faces);
    o.transform.rotateDeg = Vec3(angle(rng), angle(rng), angle(rng));
    o.transform.scale = Vec3(scale(rng), scale(rng), scale(rng));
    if (trial % 2) o.transform.scale.y = -o.transform.scale.y;
    const Scene scene = roomWith({o});
    const uint32_t handle = scene.handleOf(*scene.findObject("m"));
    const Mat3 rotation = o.transform.rotation();
    size_t matched = 0;
    for (const Face& face : scene.facesOfObject(handle)) {
      if (face.cornerNormals.empty()) continue;
      const auto& indices = o.faces[face.id.face];
      for (size_t j = 0; j < face.polygon.size(); ++j)
        for (size_t k = 0; k < indices.size(); ++k) {
          if (glm::length(o.transform.apply(o.vertices[size_t(indices[k])]) - face.polygon[j]) > 1e-12) continue;
          const Vec3 expected = glm::normalize(rotation * (o.normals[face.id.face][k] / o.transform.scale));
          EXPECT_NEAR(glm::length(face.cornerNormals[j] - expected), 0, 1e-12) << "trial " << trial;
          ++matched;
        }
    }
    EXPECT_GT(matched, o.faces.size() * 2) << "trial " << trial;
  }
}

TEST(SmoothShading, InterpolationHitsCornersStaysInFrontAndIsContinuous) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1), jitter(-0.6, 0.6);
  const Polygon3 quad{{0, 0, 0}, {1, 0, 0}, {1.2, 1, 0}, {-0.1, 0.9, 0}};
  const Vec3 up(0, 0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<Vec3> corners;
    for (size_t k = 0; k < quad.size(); ++k) corners.push_back(glm::normalize(up + Vec3(jitter(rng), jitter(rng), 0)));
    for (size_t k = 0; k < quad.size(); ++k)
      EXPECT_NEAR(glm::length(interpolatedNormal(quad, corners, up, quad[k]) - corners[k]), 0, 1e-12);
    // Inside: in front. On the fan's diagonal 0–2 both triangles give the same normal.
    const double a = u(rng), b = u(rng) * (1 - a);
    const Vec3 inside = quad[0] + a * (quad[2] - quad[0]) + b * (quad[1] - quad[0]);
    EXPECT_GT(glm::dot(interpolatedNormal(quad, corners, up, inside), up), 0);
    const Vec3 onDiagonal = quad[0] + a * (quad[2] - quad[0]);
    const Vec3 expected = glm::normalize((1 - a) * corners[0] + a * corners[2]);
    EXPECT_NEAR(glm::length(interpolatedNormal(quad, corners, up, onDiagonal) - expected), 0, 1e-12);
  }
  EXPECT_EQ(interpolatedNormal(quad, {}, up, quad[1]), up);
}

TEST(SmoothShading, EveryVertexMatchesTheReferenceAboutItsShadingNormal) {
  const std::vector<std::pair<const char*, Object>> models = {
      {"bumpy sphere", smoothed(test::bumpySphere("m", {0.3, 1.1, -0.2}, 0.4, 8, 0.3, 5), 1)},
      {"torus", smoothed(test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6), 2)},
      {"open bowl", smoothed(test::bowl("m", {-0.2, 1.3, 0.1}, 0.45, 10, 0.2, 2), 3)},
  };
  for (const auto& [name, model] : models) {
    Engine engine(roomWith({model}));
    const testing::ReferenceCheck c = testing::checkAgainstReference(engine, name);
    // The shading normal matters: many of the model's vertices differ from the flat value.
    const ExactReference reference(engine.scene());
    size_t smoothVertices = 0, changed = 0;
    for (const Engine::Receiver& r : engine.receivers()) {
      const Face* face = findFace(engine.scene(), r.face);
      if (!face || face->cornerNormals.empty()) continue;
      for (VertexId v : r.tree.vertices()) {
        const Vec3 p = r.frame.to3D(r.tree.position(v));
        ++smoothVertices;
        const double flat = reference.evaluate(p, r.frame.normal).irradiance.x;
        changed += std::abs(engine.value(r, v).irradiance.x - flat) > 1e-6 * std::max(1.0, std::abs(flat));
      }
    }
    std::printf("%s: %zu vertices (%zu on the model, %zu shaded differently than flat), %zu value errors\n", name,
                c.vertices, smoothVertices, changed, c.valueErrors);
    EXPECT_GT(c.vertices, 1000u) << name;
    EXPECT_EQ(c.valueErrors, 0u) << name;
    EXPECT_EQ(c.classErrors, 0u) << name;
    EXPECT_GT(changed, smoothVertices / 4) << name;
  }
}

TEST(SmoothShading, MovesOfASmoothMeshEqualRebuild) {
  Engine engine(roomWith({smoothed(test::torus("m", {0.1, 1.2, 0.2}, 0.45, 0.14, 16, 8, 0.6), 4)}));
  const Vec3 steps[] = {{0.05, 0.0, 0.02}, {-0.6, 0.1, 0.4}};
  int f = 0;
  for (const Vec3& step : steps) {
    Transform transform;
    transform.translate = step;
    transform.rotateDeg = Vec3(15.0 * (f + 1), 10.0 * f, 0);
    transform.scale = Vec3(1, f == 1 ? -1.2 : 1, 1);  // a mirror on the second
    const testing::MoveCheck check = testing::moveAndCompareWithRebuild(engine, "m", transform, uint64_t(f));
    EXPECT_EQ(check.diff.errors(), 0u) << "frame " << f << ": " << check.diff.firstProblem;
    ++f;
  }
  const testing::ReferenceCheck c = testing::checkAgainstReference(engine, "torus after moves");
  EXPECT_EQ(c.valueErrors, 0u);
}

}  // namespace
}  // namespace penumbra
