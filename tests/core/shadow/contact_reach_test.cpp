// A mesh's contact lines are looked for only among the faces near the receiver
// (castObjectShadow's contactReach, object_shadow.h): on seeded closed, open and inconsistently
// oriented meshes, cast on each of their own faces (the plane cuts the mesh along its whole
// section), on a floor they pierce and on planes through them, from a ceiling light and from a
// low light beside them (its corners near many faces' planes), the shadow is bit for bit the one
// that looks at every face. The same comparison checks that the silhouette items left out as
// outside the receiver's shaft (core/geom/shaft.h) add nothing: infinity looks at all of them.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/shadow/object_shadow.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

Object quad(const std::string& id, const Vec3& centre, const Vec3& normal, double half) {
  const Vec3 n = glm::normalize(normal);
  const Vec3 u = glm::normalize(glm::cross(std::abs(n.y) < 0.9 ? Vec3(0, 1, 0) : Vec3(1, 0, 0), n));
  const Vec3 v = glm::cross(n, u);
  Object o;
  o.id = id;
  o.vertices = {centre - half * u - half * v, centre + half * u - half * v, centre + half * u + half * v,
                centre - half * u + half * v};
  o.faces = {{0, 1, 2, 3}};
  return o;
}

bool sameShadow(const std::optional<SingleShadow>& x, const std::optional<SingleShadow>& y) {
  if (x.has_value() != y.has_value()) return false;
  if (!x) return true;
  if (x->penumbra != y->penumbra || x->umbra != y->umbra || x->segments.size() != y->segments.size()) return false;
  for (size_t i = 0; i < x->segments.size(); ++i) {
    const CriticalSegment &s = x->segments[i], &t = y->segments[i];
    if (s.a != t.a || s.b != t.b || s.kind != t.kind || s.lightElement != t.lightElement ||
        s.occluderElement != t.occluderElement)
      return false;
  }
  return true;
}

TEST(ContactReach, NearFacesGiveTheShadowOfEveryFace) {
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1, 1);
  Light low;  // beside the meshes at their height, facing them: near many of their faces' planes
  low.id = "low";
  low.polygon = {{2.5, 1.0, -0.4}, {2.5, 1.0, 0.4}, {2.5, 1.6, 0.4}, {2.5, 1.6, -0.4}};
  low.radiance = Vec3(1.0);
  size_t receivers = 0, contacts = 0;
  for (uint64_t seed : {1, 2}) {
    for (const test::NamedMesh& named : test::seededMeshes(seed)) {
      std::vector<Object> objects = {named.mesh};
      objects.push_back(quad("floor", {0.1, 1.0, 0.0}, {0, 1, 0}, 3.0));  // through the mesh: it pierces it
      for (int k = 0; k < 4; ++k)
        objects.push_back(quad("cut" + std::to_string(k), {0.05 * u(rng), 1.25, 0.05 * u(rng)},
                               {u(rng), u(rng), u(rng)}, 1.5));
      for (const Light& light : {test::ceilingLight(0.6), low}) {
        const Scene scene({light}, {}, objects);
        const uint32_t handle = scene.handleOf(0);
        for (const Face& receiver : scene.faces()) {
          if (!castsAsOneOccluder(scene, 0, handle, receiver)) continue;
          const PlaneFrame frame = PlaneFrame::onPlane(receiver.plane, receiver.polygon[0]);
          const auto near = castObjectShadow(scene, 0, handle, receiver, frame);
          const auto every = castObjectShadow(scene, 0, handle, receiver, frame, INFINITY);
          ++receivers;
          if (every)
            for (const CriticalSegment& s : every->segments) contacts += s.kind == SegmentKind::Contact;
          EXPECT_TRUE(sameShadow(near, every)) << named.name << " seed " << seed << " light " << light.id
                                               << " receiver " << receiver.id.object << "/" << receiver.id.face;
        }
      }
    }
  }
  EXPECT_GT(receivers, 2000u);
  EXPECT_GT(contacts, 200u) << "few contact lines: the check would not see a reach too short";
}

// Finely tessellated meshes (clusters of a few centimetres, so a shaft that left out too much
// would drop items near its sides): cast on every fifth of their own faces, on a floor and on
// planes through them, the shadow with the silhouette cut to the receiver's shaft is bit for
// bit the one with every item.
TEST(ContactReach, ShaftOfAFineMeshKeepsEverySilhouetteItemThatCasts) {
  std::mt19937_64 rng(29);
  std::uniform_real_distribution<double> u(-1, 1);
  size_t receivers = 0, segments = 0;
  const std::vector<Object> meshes = {test::bumpySphere("m", {0.1, 1.2, -0.05}, 0.5, 40, 0.1, 3),
                                      test::torus("m", {0.0, 1.3, 0.1}, 0.45, 0.15, 96, 24, 0.7)};
  for (const Object& mesh : meshes) {
    std::vector<Object> objects = {mesh, quad("floor", {0.1, 0.0, 0.0}, {0, 1, 0}, 3.0)};
    for (int k = 0; k < 3; ++k)
      objects.push_back(quad("cut" + std::to_string(k), {0.05 * u(rng), 1.25, 0.05 * u(rng)},
                             {u(rng), u(rng), u(rng)}, 1.5));
    const Scene scene({test::ceilingLight(0.6)}, {}, objects);
    const uint32_t handle = scene.handleOf(0);
    size_t index = 0;
    for (const Face& receiver : scene.faces()) {
      if (receiver.id.object == handle && index++ % 5 != 0) continue;
      if (!castsAsOneOccluder(scene, 0, handle, receiver)) continue;
      const PlaneFrame frame = PlaneFrame::onPlane(receiver.plane, receiver.polygon[0]);
      const auto near = castObjectShadow(scene, 0, handle, receiver, frame);
      const auto every = castObjectShadow(scene, 0, handle, receiver, frame, INFINITY);
      ++receivers;
      segments += every ? every->segments.size() : 0;
      EXPECT_TRUE(sameShadow(near, every)) << "receiver " << receiver.id.object << "/" << receiver.id.face;
    }
  }
  EXPECT_GT(receivers, 1000u);
  EXPECT_GT(segments, 20000u);
}

}  // namespace
}  // namespace penumbra
