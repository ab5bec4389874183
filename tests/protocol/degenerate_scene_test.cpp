// The validator and core's tolerance policy agree (issue 12, item 3): a face within
// the format's planarity tolerance is accepted and comes out of Scene lying on its
// plane; a face thinner than 1e-6 of the scene's diagonal (Tolerance::minFaceWidth)
// is refused with its key path, whether authored thin or made thin by a transform.
#include <gtest/gtest.h>

#include <random>

#include "core/scene/scene.h"
#include "protocol/scene_json.h"
#include "tests/protocol/scene_fixtures.h"

namespace penumbra::protocol {
namespace {

using json = nlohmann::json;
using testing::baseSceneJson;

std::string refusedPath(const json& scene, std::string* problem = nullptr) {
  try {
    (void)sceneFromJson(scene);
  } catch (const ValidationError& e) {
    if (problem) *problem = e.problem();
    return e.path();
  }
  return "(accepted)";
}

TEST(DegenerateScene, NearPlanarFacesAreAcceptedAndSnappedOntoTheirPlane) {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> lift(-2e-6, 2e-6);  // floor is 8.5 m across: within 1e-6 of its size
  for (int trial = 0; trial < 20; ++trial) {
    json doc = baseSceneJson();
    for (auto& v : doc["objects"][0]["vertices"]) v[1] = lift(rng);
    const Scene scene = sceneFromJson(doc);
    for (const Face& face : scene.faces()) {
      for (const Vec3& p : face.polygon)
        EXPECT_LE(std::abs(face.plane.signedDistance(p)), scene.tolerance().snap());
      EXPECT_GE(width(face.polygon), scene.tolerance().minFaceWidth());
    }
    // The authored vertices are kept (the file round-trips); only world faces are snapped.
    testing::expectSameScene(scene, sceneFromJson(sceneToJson(scene)));
  }
}

TEST(DegenerateScene, FaceAuthoredThinnerThanTheMinimumWidthIsRefusedWithItsPath) {
  json doc = baseSceneJson();
  // 1 m long, 4e-6 m wide (the scene's diagonal is ~8.5 m: minimum width 8.5e-6 m).
  doc["objects"].push_back(json::parse(R"({"id": "sliver",
      "vertices": [[0, 1, 0], [1, 1, 0], [1, 1, 4e-6], [0, 1, 4e-6]], "faces": [[0, 3, 2, 1]]})"));
  std::string problem;
  EXPECT_EQ(refusedPath(doc, &problem), "objects[3].faces[0]");
  EXPECT_NE(problem.find("thinner"), std::string::npos) << problem;
  // Twice as wide (the width of a rectangle is twice its short side): accepted.
  doc["objects"][3]["vertices"] = json::parse("[[0, 1, 0], [1, 1, 0], [1, 1, 1e-5], [0, 1, 1e-5]]");
  EXPECT_EQ(refusedPath(doc), "(accepted)");
}

TEST(DegenerateScene, FaceMadeThinByATransformIsRefusedWithItsPath) {
  json doc = baseSceneJson();
  doc["objects"][2]["transform"]["scale"] = {1, 1e-7, 1};
  std::string problem;
  const std::string path = refusedPath(doc, &problem);
  EXPECT_EQ(path.rfind("objects[2].faces[", 0), 0u) << path;
  EXPECT_NE(problem.find("thinner"), std::string::npos) << problem;
  // Scene built directly refuses the same face (one rule, in core).
  try {
    doc["objects"][2]["transform"]["scale"] = {1, 1, 1};
    Scene scene = sceneFromJson(doc);
    Object thin = scene.objects()[2];
    thin.transform.scale = {1, 1e-7, 1};
    scene.setTransform(scene.handleOf(2), thin.transform);
    FAIL() << "setTransform accepted a thin face";
  } catch (const FaceError& e) {
    EXPECT_EQ(path, "objects[2].faces[" + std::to_string(e.face()) + "]");
  }
}

}  // namespace
}  // namespace penumbra::protocol
