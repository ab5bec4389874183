// `penumbra reference` as a user runs it, checked against an independent exact
// computation: a parallel rectangular light and a parallel rectangular occluder,
// where the visible part of the light is light − (central projection of the
// occluder), an axis-aligned rectangle, integrated by the closed-form corner
// formula (no polygon clipping, no Lambert code shared with the engine).
#include <gtest/gtest.h>

#include "tests/cli/cli_test_support.h"

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>

namespace {

using nlohmann::json;

using penumbra::cli_test::kBinary;

using penumbra::cli_test::runQuiet;
using penumbra::cli_test::tempPath;

// Form factor from a point to the rectangle whose corner is straight above it at
// height h, with sides x and z (signed: odd in both).
double cornerFactor(double x, double z, double h) {
  const double X = x / h, Z = z / h;
  const double sx = std::sqrt(1 + X * X), sz = std::sqrt(1 + Z * Z);
  return (X / sx * std::atan(Z / sx) + Z / sz * std::atan(X / sz)) / (2 * M_PI);
}

struct Rect {
  double x0, x1, z0, z1;
  bool empty() const { return !(x0 < x1 && z0 < z1); }
};

// Form factor from (px, pz) at height h below a parallel rectangle.
double rectFactor(const Rect& r, double px, double pz, double h) {
  if (r.empty()) return 0;
  return cornerFactor(r.x1 - px, r.z1 - pz, h) - cornerFactor(r.x0 - px, r.z1 - pz, h) -
         cornerFactor(r.x1 - px, r.z0 - pz, h) + cornerFactor(r.x0 - px, r.z0 - pz, h);
}

Rect intersect(const Rect& a, const Rect& b) {
  return {std::max(a.x0, b.x0), std::min(a.x1, b.x1), std::max(a.z0, b.z0), std::min(a.z1, b.z1)};
}

json quad(double x0, double x1, double y, double z0, double z1, bool up) {
  // Counter-clockwise seen from above (+y) when `up`.
  json v = {{x0, y, z0}, {x0, y, z1}, {x1, y, z1}, {x1, y, z0}};
  if (!up) v = {{x0, y, z0}, {x1, y, z0}, {x1, y, z1}, {x0, y, z1}};
  return v;
}

TEST(ReferenceCli, MeshMatchesClosedFormWithParallelOccluder) {
  const double lightY = 2.0, occluderY = 0.8, radiance = 7.5;
  const Rect light{-0.5, 0.7, -0.4, 0.3};
  const Rect occluder{-0.4, 0.3, -0.15, 0.4};
  json scene = {
      {"format", "penumbra.scene"},
      {"version", 1},
      {"lights", {{{"id", "lamp"},
                   {"polygon", quad(light.x0, light.x1, lightY, light.z0, light.z1, false)},
                   {"radiance", {radiance, radiance, radiance}}}}},
      {"objects",
       {{{"id", "floor"}, {"vertices", quad(-2, 2, 0, -2, 2, true)}, {"faces", {{0, 1, 2, 3}}}},
        {{"id", "card"},
         {"vertices", quad(occluder.x0, occluder.x1, occluderY, occluder.z0, occluder.z1, true)},
         {"faces", {{0, 1, 2, 3}}}}}}};
  const std::string scenePath = tempPath("parallel.scene.json");
  const std::string meshPath = tempPath("parallel.mesh.json");
  std::ofstream(scenePath) << scene.dump(2);

  ASSERT_EQ(runQuiet("reference " + scenePath + " --grid 12 --out " + meshPath), 0);
  json mesh;
  std::ifstream(meshPath) >> mesh;
  ASSERT_EQ(mesh["format"], "penumbra.mesh");
  ASSERT_EQ(mesh["receivers"].size(), 2u);

  const double peak = radiance * M_PI * rectFactor(light, 0.1, 0, lightY);
  size_t checked = 0, penumbra = 0, umbra = 0;
  for (const json& receiver : mesh["receivers"]) {
    const bool onFloor = receiver["object"] == "floor";
    const double h = lightY - (onFloor ? 0.0 : occluderY);
    const auto& positions = receiver["positions"];
    ASSERT_EQ(positions.size(), receiver["irradiance"].size());
    ASSERT_EQ(positions.size(), receiver["class"].size());
    ASSERT_GE(positions.size(), 13u * 13u);
    for (size_t i = 0; i < positions.size(); ++i) {
      const double px = positions[i][0], pz = positions[i][2];
      double factor = rectFactor(light, px, pz, h);
      Rect shadow{};
      if (onFloor) {
        // The occluder seen from p, projected onto the light's plane.
        const double k = lightY / occluderY;
        shadow = intersect(light, {px + (occluder.x0 - px) * k, px + (occluder.x1 - px) * k,
                                   pz + (occluder.z0 - pz) * k, pz + (occluder.z1 - pz) * k});
        factor -= rectFactor(shadow, px, pz, h);
      }
      const double expected = radiance * M_PI * factor;
      for (int c = 0; c < 3; ++c) {
        const double value = receiver["irradiance"][i][c];
        EXPECT_NEAR(value, expected, 1e-9 * std::abs(expected) + 1e-12 * peak)
            << receiver["object"] << " vertex " << i << " at " << px << ", " << pz;
      }
      const std::string cls = receiver["class"][i];
      // A vertex exactly on a shadow boundary may take either class (SCENE_FORMAT.md).
      const bool onBoundary = !shadow.empty() && (shadow.x1 - shadow.x0 < 1e-9 || shadow.z1 - shadow.z0 < 1e-9);
      if (onBoundary) {
      } else if (shadow.empty()) {
        EXPECT_EQ(cls, "lit") << receiver["object"] << " vertex " << i;
      } else if (std::abs(factor) < 1e-12) {
        EXPECT_EQ(cls, "umbra");
        ++umbra;
      } else {
        EXPECT_EQ(cls, "penumbra") << "shadow " << shadow.x0 << ".." << shadow.x1 << " x "
                                   << shadow.z0 << ".." << shadow.z1 << " at " << px << ", " << pz;
        ++penumbra;
      }
      ++checked;
    }
  }
  EXPECT_GT(penumbra, 10u);  // the scene really has a soft shadow on the grid
  EXPECT_GT(umbra, 0u);
  std::printf("checked %zu vertices (%zu penumbra, %zu umbra)\n", checked, penumbra, umbra);
}

TEST(ReferenceCli, RefusesBadSceneWithKeyPathAndExitTwo) {
  const std::string scenePath = tempPath("bad.scene.json");
  std::ofstream(scenePath) << R"({"format": "penumbra.scene", "version": 1,
    "lights": [{"id": "l", "polygon": [[0,2,0],[1,2,0],[1,2,1]], "radiance": [1,1,1]}],
    "objects": [{"id": "a", "vertices": [[0,0,0],[1,0,0],[1,0,1]], "faces": [[0, 1, 7]]}]})";
  const std::string errPath = tempPath("bad.err");
  const int status =
      std::system((kBinary + " validate " + scenePath + " 2>" + errPath + " >/dev/null").c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
  std::ifstream err(errPath);
  const std::string message((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  EXPECT_NE(message.find("objects[0].faces[0]"), std::string::npos) << message;
  EXPECT_EQ(runQuiet("reference " + scenePath + " --grid 4 --out " + tempPath("never.mesh.json")), 2);
}

TEST(ReferenceCli, UsageErrorsExitTwo) {
  EXPECT_EQ(runQuiet("no-such-command"), 2);
  EXPECT_EQ(runQuiet("reference"), 2);
  EXPECT_EQ(runQuiet("reference x.json --grid zero --out y"), 2);
}

}  // namespace
