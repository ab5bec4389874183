// Round trip (issue 40): scene → GLB (the exporter of `penumbra build SCENE --out X.glb`) →
// import gives the scene back (docs/SCENE_FORMAT.md "GLB round trip"): per object, by id (node
// name = object id) and in order, the same faces in order, each with the same corners from the
// same first corner (the same winding), the same welded vertices and the same material; the same
// lights (ids, radiance exactly, polygons) and camera (exactly). Positions within float32
// precision, as the GLB stores them: 4 float ulps of the scene's largest coordinate. Over the
// bundled scenes and seeded generated models.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>
#include <sstream>

#include "core/engine/engine.h"
#include "interchange/glb_export.h"
#include "interchange/scene_import.h"
#include "protocol/scene_json.h"
#include "scenegen/model_scene.h"

namespace penumbra::interchange {
namespace {

ImportResult roundTrip(const Scene& scene) {
  Engine engine(scene);
  const GlbFile glb = meshToGlb(engine.scene(), engine.mesh());
  ImportOptions options;
  options.studio = false;  // the scene's own lights come back
  return importSceneBytes(glb.bytes, "round_trip.glb", {}, options);
}

// 4 float ulps of the largest coordinate of faces and lights.
double floatTolerance(const Scene& scene) {
  double largest = 0;
  auto add = [&](const Polygon3& polygon) {
    for (const Vec3& p : polygon)
      largest = std::max({largest, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  };
  for (const Face& face : scene.faces()) add(face.polygon);
  for (const Light& light : scene.lights()) add(light.polygon);
  return 4 * std::ldexp(largest, -23);
}

bool near(const Vec3& a, const Vec3& b, double tolerance) {
  return std::abs(a.x - b.x) <= tolerance && std::abs(a.y - b.y) <= tolerance &&
         std::abs(a.z - b.z) <= tolerance;
}

// The same corners in the same cyclic order (any first corner).
bool sameCycle(const Polygon3& a, const Polygon3& b, double tolerance) {
  if (a.size() != b.size()) return false;
  for (size_t r = 0; r < a.size(); ++r) {
    bool all = true;
    for (size_t i = 0; i < a.size() && all; ++i) all = near(a[i], b[(i + r) % b.size()], tolerance);
    if (all) return true;
  }
  return false;
}

std::string text(const Polygon3& polygon) {
  std::ostringstream out;
  out.precision(9);
  for (const Vec3& p : polygon) out << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return out.str();
}

Material materialOf(const Scene& scene, const Object& object) {
  const std::optional<size_t> m = scene.findMaterial(object.material);
  Material material = m ? scene.materials()[*m] : Material{};
  material.id.clear();  // the name may change (made unique); the parameters may not
  return material;
}

// Distinct corner positions of an object's faces (its welded vertices).
size_t weldedVertices(const Scene& scene, uint32_t handle) {
  std::set<std::array<double, 3>> seen;
  for (const Face& face : scene.facesOfObject(handle))
    for (const Vec3& p : face.polygon) seen.insert({p.x, p.y, p.z});
  return seen.size();
}

// How `imported` differs from `original`, one line each; empty when it is the same scene.
std::vector<std::string> differences(const Scene& original, const Scene& imported) {
  std::vector<std::string> out;
  const double tolerance = floatTolerance(original);
  std::vector<std::string> ids, importedIds;
  for (const Object& object : original.objects()) ids.push_back(object.id);
  for (const Object& object : imported.objects()) importedIds.push_back(object.id);
  if (ids != importedIds) return {"object ids differ"};
  for (size_t i = 0; i < ids.size(); ++i) {
    const uint32_t a = original.handleOf(i), b = imported.handleOf(i);
    const std::span<const Face> faces = original.facesOfObject(a), back = imported.facesOfObject(b);
    const std::string name = "'" + ids[i] + "'";
    if (faces.size() != back.size()) {
      out.push_back(name + ": " + std::to_string(faces.size()) + " faces, " +
                    std::to_string(back.size()) + " back");
      continue;
    }
    for (size_t f = 0; f < faces.size(); ++f)
      if (!sameCycle(faces[f].polygon, back[f].polygon, tolerance))
        out.push_back(name + " face " + std::to_string(f) + ": " + text(faces[f].polygon) +
                      " came back as " + text(back[f].polygon));
    if (weldedVertices(original, a) != weldedVertices(imported, b))
      out.push_back(name + ": " + std::to_string(weldedVertices(original, a)) +
                    " welded vertices, " + std::to_string(weldedVertices(imported, b)) + " back");
    if (!(materialOf(original, original.objects()[i]) ==
          materialOf(imported, imported.objects()[i])))
      out.push_back(name + ": material differs");
  }
  if (original.camera().has_value() != imported.camera().has_value()) {
    out.push_back("camera present in one only");
  } else if (original.camera()) {
    const Camera &a = *original.camera(), &b = *imported.camera();
    if (a.position != b.position || a.target != b.target || a.up != b.up ||
        a.projection != b.projection || a.fovYDeg != b.fovYDeg || a.height != b.height ||
        a.near != b.near || a.far != b.far)
      out.push_back("camera differs");
  }
  if (original.lights().size() != imported.lights().size())
    return out.push_back("light count differs"), out;
  for (size_t l = 0; l < original.lights().size(); ++l) {
    const Light &a = original.lights()[l], &b = imported.lights()[l];
    if (a.id != b.id) out.push_back("light " + a.id + " came back as " + b.id);
    if (a.radiance != b.radiance) out.push_back("light " + a.id + ": radiance differs");
    if (!sameCycle(a.polygon, b.polygon, tolerance))
      out.push_back("light " + a.id + ": " + text(a.polygon) + " came back as " + text(b.polygon));
  }
  return out;
}

std::string joined(const std::vector<std::string>& lines) {
  std::string all;
  for (size_t i = 0; i < lines.size() && i < 20; ++i) all += "  " + lines[i] + "\n";
  if (lines.size() > 20) all += "  … " + std::to_string(lines.size() - 20) + " more\n";
  return all;
}

TEST(GlbRoundTrip, TheComparisonCanFail) {
  const Scene scene =
      protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json");
  EXPECT_EQ(joined(differences(scene, scene)), "");
  const double tolerance = floatTolerance(scene);
  std::vector<Object> objects = scene.objects();
  for (Vec3& v : objects[0].vertices) v.x += 8 * tolerance;  // one object moved by 8 float ulps
  std::vector<Material> materials = scene.materials();
  materials[0].albedo.y += 0.01;
  std::vector<Light> lights = scene.lights();
  lights[0].radiance.z *= 1 + 1e-12;
  Camera camera = *scene.camera();
  camera.fovYDeg += 1e-9;
  const std::vector<std::string> found =
      differences(scene, Scene(lights, materials, objects, camera));
  EXPECT_FALSE(found.empty());
  const std::string all = joined(found);
  EXPECT_NE(all.find("'" + objects[0].id + "' face 0"), std::string::npos) << all;
  EXPECT_NE(all.find("material differs"), std::string::npos) << all;
  EXPECT_NE(all.find("radiance differs"), std::string::npos) << all;
  EXPECT_NE(all.find("camera differs"), std::string::npos) << all;
}

TEST(GlbRoundTrip, BundledScenes) {
  for (const auto& entry :
       std::filesystem::directory_iterator(std::string(PENUMBRA_SOURCE_DIR) + "/scenes")) {
    if (!entry.path().filename().string().ends_with(".scene.json")) continue;
    SCOPED_TRACE(entry.path().filename().string());
    const Scene scene = protocol::loadSceneFile(entry.path().string());
    const ImportResult back = roundTrip(scene);
    EXPECT_EQ(joined(differences(scene, back.scene)), "") << back.report.summary();
    EXPECT_EQ(back.report.repaired("coplanar_triangles_joined"), 0u);
  }
}

// --scale (or the upload's scale) scales the camera with the geometry.
TEST(GlbRoundTrip, TheCameraScalesWithTheGeometry) {
  const Scene scene = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json");
  Engine engine(scene);
  ImportOptions options;
  options.scale = 2;
  const ImportResult back = importSceneBytes(meshToGlb(engine.scene(), engine.mesh()).bytes, "c.glb", {}, options);
  ASSERT_TRUE(back.scene.camera());
  EXPECT_EQ(back.scene.camera()->position, 2.0 * scene.camera()->position);
  EXPECT_EQ(back.scene.camera()->target, 2.0 * scene.camera()->target);
  EXPECT_EQ(back.scene.camera()->fovYDeg, scene.camera()->fovYDeg);
}

// Seeded: model kind, triangle count, shape seed and resting or floating, as `penumbra generate
// --model` makes them.
TEST(GlbRoundTrip, GeneratedModels) {
  std::mt19937_64 random(40);
  const ModelKind kinds[] = {ModelKind::Teapot, ModelKind::TorusKnot, ModelKind::Blob,
                             ModelKind::Bowl, ModelKind::Scan};
  for (int run = 0; run < 6; ++run) {
    ModelSceneOptions options;
    options.kind = kinds[random() % 5];
    options.triangles = minModelTriangles(options.kind) * int(1 + random() % 2);
    options.seed = random();
    options.rest = random() % 2;
    SCOPED_TRACE(std::string(modelKindName(options.kind)) + " " +
                 std::to_string(options.triangles) + " triangles, seed " +
                 std::to_string(options.seed) + (options.rest ? ", resting" : ", floating"));
    const Scene scene = makeModelScene(options);
    const ImportResult back = roundTrip(scene);
    EXPECT_EQ(joined(differences(scene, back.scene)), "") << back.report.summary();
  }
}

}  // namespace
}  // namespace penumbra::interchange
