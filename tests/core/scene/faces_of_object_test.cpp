// Scene::facesOfObject (core/scene/scene.h) reads an index of each object's faces kept beside
// faces(): after any sequence of adds, removes, moves and re-handlings it must still name
// exactly the faces of faces() with that object's handle, in order, and nothing for a handle
// the scene does not hold.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "scenegen/scene_parts.h"

namespace penumbra {
namespace {

// An object of one to three boxes (6, 12 or 18 faces), so removals shift the index by
// different amounts.
Object boxes(const std::string& id, std::mt19937_64& rng) {
  Object object;
  object.id = id;
  const int count = int(rng() % 3) + 1;
  for (int b = 0; b < count; ++b) {
    const Vec3 lo(uniform(rng, -5, 4), uniform(rng, 0, 2), uniform(rng, -5, 4));
    addBox(object, lo, lo + Vec3(uniform(rng, 0.2, 1), uniform(rng, 0.2, 1), uniform(rng, 0.2, 1)));
  }
  return object;
}

void expectIndexMatchesFaces(const Scene& scene, uint32_t handlesBelow) {
  for (uint32_t handle = 0; handle <= handlesBelow; ++handle) {
    std::vector<const Face*> expected;
    for (const Face& face : scene.faces())
      if (face.id.object == handle) expected.push_back(&face);
    const auto found = scene.facesOfObject(handle);
    ASSERT_EQ(found.size(), expected.size()) << "handle " << handle;
    for (size_t f = 0; f < found.size(); ++f) EXPECT_EQ(&found[f], expected[f]) << "handle " << handle << " face " << f;
    EXPECT_EQ(found.empty(), !scene.indexOfHandle(handle).has_value()) << "handle " << handle;
  }
}

TEST(FacesOfObject, NamesEachObjectsFacesAfterRandomAddsRemovesAndMoves) {
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937_64 rng(seed);
    Light light{"light", {{-0.5, 9, -0.5}, {-0.5, 9, 0.5}, {0.5, 9, 0.5}, {0.5, 9, -0.5}}, Vec3(10)};
    std::vector<Object> objects;
    for (int o = 0; o < 4; ++o) objects.push_back(boxes("o" + std::to_string(o), rng));
    Scene scene({light}, {}, objects);
    int named = 4;
    for (int step = 0; step < 40; ++step) {
      const size_t count = scene.objects().size();
      const int op = int(rng() % 3);
      if (op == 0 || count == 0) {
        scene.addObject(boxes("o" + std::to_string(named++), rng));
      } else if (op == 1) {
        scene.removeObject(scene.handleOf(rng() % count));
      } else {
        Transform moved;
        moved.translate = Vec3(uniform(rng, -1, 1), uniform(rng, 0, 1), uniform(rng, -1, 1));
        moved.rotateDeg = Vec3(0, uniform(rng, 0, 90), 0);
        scene.setTransform(scene.handleOf(rng() % count), moved);
      }
      expectIndexMatchesFaces(scene, scene.nextHandle());
    }
    // Read back as JSON would (handles 0..n-1), then given the edited scene's handles.
    std::vector<uint32_t> handles;
    for (size_t o = 0; o < scene.objects().size(); ++o) handles.push_back(scene.handleOf(o));
    Scene copy({light}, {}, scene.objects());
    copy.setHandles(handles, scene.nextHandle());
    expectIndexMatchesFaces(copy, copy.nextHandle());
  }
}

}  // namespace
}  // namespace penumbra
