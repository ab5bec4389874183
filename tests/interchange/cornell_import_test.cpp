// The Cornell-like OBJ in millimetres, imported and built as a user does it
// (`penumbra import`, `penumbra build`): the light sits where the file puts it and
// every vertex of the DM mesh equals the independent exact reference
// (DESIGN.md invariant 1: 1e-9 relative, 1e-12 of the peak).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <map>
#include <tuple>

#include "core/engine/engine.h"
#include "core/reference/exact_irradiance.h"
#include "interchange/obj_import.h"
#include "interchange_fixtures.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"

namespace penumbra::interchange {
namespace {

using testing::kData;
using testing::runPenumbra;
using testing::scratchDir;

bool close(double value, double truth, double peak) {
  return std::abs(value - truth) <= 1e-9 * std::abs(truth) + 1e-12 * peak;
}

bool closeRgb(const Vec3& value, const Vec3& truth, double peak) {
  return close(value.x, truth.x, peak) && close(value.y, truth.y, peak) && close(value.z, truth.z, peak);
}

// Mesh vertices: a location that repeats (one copy per side of a value jump) must
// have a copy equal to the reference there, or else (a contact seen from one side)
// every copy must be the limit from its side: the reference a little way into a
// triangle that uses it (the engine's own test, tests/core/engine/engine_build_test.cpp).
size_t meshMismatches(const Scene& scene, const Mesh& mesh, const ExactReference& reference, double peak) {
  const double onPlane = scene.tolerance().onPlane();
  size_t errors = 0;
  for (const ReceiverMesh& r : mesh.receivers) {
    std::map<std::tuple<double, double, double>, std::vector<size_t>> copies;
    for (size_t i = 0; i < r.positions.size(); ++i) copies[{r.positions[i].x, r.positions[i].y, r.positions[i].z}].push_back(i);
    std::vector<size_t> triangleOf(r.positions.size());
    for (size_t t = 0; t < r.triangles.size(); ++t)
      for (uint32_t i : r.triangles[t]) triangleOf[i] = t;
    auto limitMatches = [&](size_t i) {
      const auto& t = r.triangles[triangleOf[i]];
      const Vec3 inside = (r.positions[t[0]] + r.positions[t[1]] + r.positions[t[2]]) / 3.0;
      const Vec3 p = r.positions[i];
      for (double s = 1.0 / 1024; s <= 1; s *= 2) {
        const Vec3 q = p + s * (inside - p);
        const bool clear = std::all_of(scene.faces().begin(), scene.faces().end(), [&](const Face& f) {
          return std::abs(f.plane.signedDistance(p)) > onPlane || std::abs(glm::dot(f.plane.normal, r.normal)) > 1 - 1e-12 ||
                 std::abs(f.plane.signedDistance(q)) > 2 * onPlane;
        });
        if (clear) return glm::length(r.irradiance[i] - reference.evaluate(q, r.normal).irradiance) <= 1e-3 * peak;
      }
      return false;
    };
    for (const auto& [at, indices] : copies) {
      const PointIrradiance truth = reference.evaluate(r.positions[indices[0]], r.normal);
      bool matched = false;
      for (size_t i : indices) matched |= closeRgb(r.irradiance[i], truth.irradiance, peak);
      if (!matched) matched = std::all_of(indices.begin(), indices.end(), limitMatches);
      if (!matched && errors++ < 5)
        ADD_FAILURE() << "face " << r.face.object << "/" << r.face.face << " vertex at (" << std::get<0>(at) << ", "
                      << std::get<1>(at) << ", " << std::get<2>(at) << "): " << r.irradiance[indices[0]].x
                      << ", reference " << truth.irradiance.x;
    }
  }
  return errors;
}

// The built mesh (every output vertex) and the engine's own DM vertices equal the
// exact reference; `mesh` is the engine's mesh of `scene` (from the CLI or in process).
void expectMatchesExactReference(const Scene& scene, const Mesh& mesh, const char* name, size_t minPenumbra) {
  EXPECT_EQ(mesh.receivers.size(), size_t(std::count_if(scene.faces().begin(), scene.faces().end(),
                                                         [&](const Face& f) { return scene.receivesLight(f); })));
  const ExactReference reference(scene);
  double peak = 0;
  for (const ReceiverMesh& r : mesh.receivers)
    for (const Vec3& e : r.irradiance) peak = std::max({peak, e.x, e.y, e.z});
  EXPECT_GT(peak, 0);
  EXPECT_EQ(meshMismatches(scene, mesh, reference, peak), 0u);

  // And the DM vertices themselves (no display lattice), in process.
  Engine engine(scene);
  size_t vertices = 0, errors = 0, penumbra = 0;
  for (const Engine::Receiver& receiver : engine.receivers())
    for (VertexId v : receiver.tree.vertices()) {
      const Vec3 p = receiver.frame.to3D(receiver.tree.position(v));
      const PointIrradiance truth = reference.evaluate(p, receiver.frame.normal);
      ++vertices;
      penumbra += truth.lightClass == LightClass::Penumbra;
      if (!closeRgb(engine.value(receiver, v).irradiance, truth.irradiance, peak) && errors++ < 5)
        ADD_FAILURE() << "DM vertex " << v.index << ": " << engine.value(receiver, v).irradiance.x << " vs "
                      << truth.irradiance.x;
    }
  EXPECT_EQ(errors, 0u);
  EXPECT_GE(penumbra, minPenumbra) << "the blocks cast soft shadows";
  std::printf("[ %s ] %zu DM vertices (%zu penumbra), %zu mesh vertices, peak %.6g W/m^2\n", name, vertices,
              penumbra, mesh.vertexCount(), peak);
}

TEST(CornellImport, ImportedMillimetreBoxBuildsAndMatchesTheExactReference) {
  const auto dir = scratchDir();
  const std::string scenePath = (dir / "cornell.scene.json").string();
  const std::string meshPath = (dir / "cornell.mesh.json").string();
  ASSERT_EQ(runPenumbra("import " + kData + "/cornell_mm.obj --scale 0.001 --out " + scenePath + " --report " +
                            (dir / "report.json").string(),
                        dir / "import"),
            0);
  ASSERT_EQ(runPenumbra("build " + scenePath + " --out " + meshPath, dir / "build"), 0);

  // What was repaired: the left wall is not planar (as in the measured data).
  std::ifstream reportFile(dir / "report.json");
  const nlohmann::json report = nlohmann::json::parse(reportFile);
  EXPECT_EQ(report["repairs"].value("non_planar_polygons_split", 0), 1) << report.dump(2);
  // No faces overlap in one plane: the blocks have no bottoms, and the light (in the
  // ceiling's plane) is no face.
  EXPECT_FALSE(report["repairs"].contains("coplanar_overlapping_face_pairs")) << report.dump(2);
  EXPECT_FALSE(report["repairs"].contains("covered_coplanar_faces_dropped")) << report.dump(2);
  EXPECT_EQ(report["lights"], 1);
  EXPECT_EQ(report["objects"], 7);

  const Scene scene = protocol::loadSceneFile(scenePath);
  ASSERT_EQ(scene.lights().size(), 1u);
  const Light& light = scene.lights()[0];
  const Polygon3 inFile = {{343.0, 548.8, 227.0}, {343.0, 548.8, 332.0}, {213.0, 548.8, 332.0}, {213.0, 548.8, 227.0}};
  ASSERT_EQ(light.polygon.size(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(light.polygon[k], inFile[k] * 0.001) << "light corner " << k;
  EXPECT_EQ(light.radiance, Vec3(17, 12, 4));
  EXPECT_LT(light.plane().normal.y, -0.999);

  const Mesh mesh = protocol::loadMeshFile(meshPath, scene);
  // Every face that some of the light is in front of: all but the ceiling (the
  // light's own plane) and the four block sides that face away from it.
  EXPECT_EQ(mesh.receivers.size(), 11u);
  expectMatchesExactReference(scene, mesh, "cornell_mm", 100);
}

TEST(CornellImport, WilliamsStyleBoxBuildsAndMatchesTheExactReference) {
  const ImportResult imported = importObjFile(kData + "/williams_style.obj", {});
  Engine engine(imported.scene);
  const Mesh mesh = engine.mesh();
  expectMatchesExactReference(imported.scene, mesh, "williams_style", 5);
}

}  // namespace
}  // namespace penumbra::interchange
