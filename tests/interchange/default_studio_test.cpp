// Importing a bare model (no emissive faces): it goes into the default studio, scaled to fit and
// resting on the floor under the light, and the report says so; the surface repairs (welding,
// orientation, closed components, non-manifold edges) are counted per object. OBJ text written
// by the test; the checks of winding and volume are the test's own.
#include "interchange/default_studio.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <map>
#include <random>
#include <sstream>

#include "core/geom/polygon.h"
#include "interchange/obj_import.h"
#include "interchange/scene_import.h"
#include "interchange_fixtures.h"
#include "protocol/scene_json.h"
#include "protocol/validation_error.h"

namespace penumbra::interchange {
namespace {

using testing::runPenumbra;
using testing::scratchDir;
using testing::writeFile;

// The corners of the box [lo, lo + size] in OBJ order, then its six faces wound outward (face
// `flip` reversed); indices counted from `first` (1 for the file's first vertex).
std::string boxObj(const Vec3& lo, const Vec3& size, int first, int flip = -1) {
  std::ostringstream text;
  text.precision(17);
  for (int i = 0; i < 8; ++i) {
    const Vec3 p = lo + size * Vec3((i == 1 || i == 2 || i == 5 || i == 6) ? 1 : 0,
                                    (i == 2 || i == 3 || i == 6 || i == 7) ? 1 : 0, i >= 4 ? 1 : 0);
    text << "v " << p.x << " " << p.y << " " << p.z << "\n";
  }
  const int faces[6][4] = {{1, 2, 6, 5}, {4, 8, 7, 3}, {1, 4, 3, 2},
                           {5, 6, 7, 8}, {1, 5, 8, 4}, {2, 3, 7, 6}};
  for (int f = 0; f < 6; ++f) {
    text << "f";
    for (int k = 0; k < 4; ++k) text << " " << first - 1 + faces[f][f == flip ? 3 - k : k];
    text << "\n";
  }
  return text.str();
}

ImportResult importText(const std::string& obj, const std::string& name,
                        const ImportOptions& options = {}) {
  return importObjText(obj, {}, options, name);
}

const Object& objectNamed(const Scene& scene, const std::string& id) {
  const auto index = scene.findObject(id);
  EXPECT_TRUE(index) << id;
  return scene.objects()[index.value_or(0)];
}

Bounds boundsOf(const Object& object) {
  Bounds b{Vec3(INFINITY), Vec3(-INFINITY)};
  for (const auto& face : object.faces)
    for (int i : face) {
      b.min = glm::min(b.min, object.vertices[size_t(i)]);
      b.max = glm::max(b.max, object.vertices[size_t(i)]);
    }
  return b;
}

double signedVolume(const Object& object) {
  double sum = 0;
  for (const auto& f : object.faces)
    for (size_t k = 1; k + 1 < f.size(); ++k)
      sum += glm::dot(object.vertices[size_t(f[0])],
                      glm::cross(object.vertices[size_t(f[k])], object.vertices[size_t(f[k + 1])]));
  return sum / 6;
}

// Each undirected edge of the object's faces shared by exactly two faces running opposite ways.
bool consistentlyClosed(const Object& object) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& f : object.faces)
    for (size_t k = 0; k < f.size(); ++k) ++directed[{f[k], f[(k + 1) % f.size()]}];
  for (const auto& [edge, count] : directed)
    if (count != 1 || !directed.count({edge.second, edge.first})) return false;
  return true;
}

const ObjectMeshFacts& factsOf(const ImportReport& report, const std::string& object) {
  for (const ObjectMeshFacts& facts : report.meshes)
    if (facts.object == object) return facts;
  ADD_FAILURE() << "no mesh facts for " << object;
  static const ObjectMeshFacts none;
  return none;
}

TEST(DefaultStudio, BareCubeWithOneFlippedFaceGoesIntoTheStudio) {
  const ImportResult result =
      importText("o cube\n" + boxObj(Vec3(10, 20, 30), Vec3(0.5), 1, 2), "cube.obj");
  const ImportReport& report = result.report;
  const Scene& scene = result.scene;
  ASSERT_TRUE(report.studio) << report.summary();
  EXPECT_EQ(report.studio->scale, 1);  // 0.5 m fits
  EXPECT_EQ(report.studio->sentence,
            "no lights in cube.obj: placed it in the default studio (6 × 3 × 6 m room, 1 m² light "
            "just under the "
            "3 m ceiling), not scaled (largest extent 0.5 m, within 0.1–2 m), resting on the floor "
            "at the room's "
            "centre");
  EXPECT_NE(report.summary().find(report.studio->sentence), std::string::npos);
  EXPECT_EQ(report.toJson()["studio"]["sentence"], report.studio->sentence);

  // The flipped face is turned back and counted; the cube is one closed component, outward.
  EXPECT_EQ(report.repaired("faces_flipped_for_consistent_orientation"), 1u) << report.summary();
  const ObjectMeshFacts& facts = factsOf(report, "cube");
  EXPECT_EQ(facts.facesFlipped, 1u);
  EXPECT_EQ(facts.components, 1u);
  EXPECT_EQ(facts.closedComponents, 1u);
  EXPECT_NE(report.summary().find("'cube': 6 faces, 1 component, 1 closed; 1 face flipped"),
            std::string::npos)
      << report.summary();
  const Object& cube = objectNamed(scene, "cube");
  EXPECT_TRUE(consistentlyClosed(cube));
  EXPECT_NEAR(signedVolume(cube), 0.125, 1e-12);

  // Resting on the floor at the room's centre, the light above it.
  const Bounds placed = boundsOf(cube);
  EXPECT_EQ(placed.min.y, 0);
  EXPECT_NEAR(placed.max.y, 0.5, 1e-12);
  EXPECT_NEAR(placed.center().x, 0, 1e-12);
  EXPECT_NEAR(placed.center().z, 0, 1e-12);
  ASSERT_EQ(scene.lights().size(), 1u);
  const Light& light = scene.lights()[0];
  EXPECT_EQ(light.radiance, Vec3(kStudioRadiance));
  for (const Vec3& p : light.polygon) {
    EXPECT_GT(p.y, placed.max.y);
    EXPECT_EQ(p.y, kStudioLightY);
  }
  const Vec3 lightCentre = centroid(light.polygon);
  EXPECT_NEAR(lightCentre.x, placed.center().x, 1e-12);
  EXPECT_NEAR(lightCentre.z, placed.center().z, 1e-12);
  EXPECT_LT(glm::dot(newellVector(light.polygon), Vec3(0, 1, 0)), 0);  // facing down at the model

  // The room: floor at y = 0 facing up, and the walls; the floor lit.
  const Object& floor = objectNamed(scene, "studio_floor");
  EXPECT_EQ(boundsOf(floor).min.y, 0);
  EXPECT_EQ(boundsOf(floor).max.y, 0);
  EXPECT_GT(Scene::worldPolygons(floor)[0].size(), 0u);
  EXPECT_GT(glm::dot(newellVector(Scene::worldPolygons(floor)[0]), Vec3(0, 1, 0)), 0);
  for (const char* id :
       {"studio_ceiling", "studio_wall_n", "studio_wall_s", "studio_wall_e", "studio_wall_w"})
    objectNamed(scene, id);
  EXPECT_EQ(scene.objects().size(), 7u);
  EXPECT_EQ(report.objects, 7u);
  EXPECT_EQ(report.lights, 1u);
  EXPECT_TRUE(result.sceneJson.contains("camera"));
  // The file's object alone is in `meshes`.
  ASSERT_EQ(report.meshes.size(), 1u);
}

TEST(DefaultStudio, ClosedCubeAndOpenGridAreTwoComponentsOneClosed) {
  std::string obj = "o thing\n" + boxObj(Vec3(0), Vec3(0.4), 1);
  // A 3 × 3 grid of quads beside the cube, in the same object.
  for (int i = 0; i <= 3; ++i)
    for (int j = 0; j <= 3; ++j)
      obj += "v " + std::to_string(1 + 0.2 * i) + " 0 " + std::to_string(0.2 * j) + "\n";
  auto at = [](int i, int j) { return std::to_string(9 + i * 4 + j); };
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      obj +=
          "f " + at(i, j) + " " + at(i, j + 1) + " " + at(i + 1, j + 1) + " " + at(i + 1, j) + "\n";
  const ImportResult result = importText(obj, "two.obj");
  const ObjectMeshFacts& facts = factsOf(result.report, "thing");
  EXPECT_EQ(facts.components, 2u) << result.report.summary();
  EXPECT_EQ(facts.closedComponents, 1u);
  EXPECT_EQ(facts.boundaryEdges, 12u);
  EXPECT_EQ(facts.faces, 15u);
  EXPECT_EQ(facts.facesFlipped, 0u);
  EXPECT_NE(result.report.summary().find("'thing': 15 faces, 2 components, 1 closed"),
            std::string::npos)
      << result.report.summary();
  const nlohmann::json meshes = result.report.toJson()["meshes"];
  ASSERT_EQ(meshes.size(), 1u);
  EXPECT_EQ(meshes[0]["components"], 2);
  EXPECT_EQ(meshes[0]["closed_components"], 1);
}

TEST(DefaultStudio, InchScaledModelIsScaledToFit) {
  // 200 units across (inches, say): scaled to 1 m, the scale said in the sentence.
  const ImportResult result =
      importText("o big\n" + boxObj(Vec3(-100, 5, -40), Vec3(200, 80, 120), 1), "big.obj");
  ASSERT_TRUE(result.report.studio);
  EXPECT_DOUBLE_EQ(result.report.studio->scale, 0.005);
  EXPECT_NE(result.report.studio->sentence.find("scaled by 0.005 (largest extent 200 → 1 m)"),
            std::string::npos)
      << result.report.studio->sentence;
  const Bounds placed = boundsOf(objectNamed(result.scene, "big"));
  EXPECT_NEAR(placed.max.x - placed.min.x, 1, 1e-12);
  EXPECT_NEAR(placed.max.y - placed.min.y, 0.4, 1e-12);
  EXPECT_EQ(placed.min.y, 0);
  // --scale first: 200 × 0.0254 = 5.08 m is still too big, scaled by 1/5.08 more.
  ImportOptions options;
  options.scale = 0.0254;
  const ImportResult inches =
      importText("o big\n" + boxObj(Vec3(-100, 5, -40), Vec3(200, 80, 120), 1), "big.obj", options);
  EXPECT_NEAR(inches.report.studio->scale, 1 / 5.08, 1e-12);
  // A tiny model (1 cm) is scaled up to 1 m too.
  const ImportResult tiny = importText("o tiny\n" + boxObj(Vec3(0), Vec3(0.01), 1), "tiny.obj");
  EXPECT_NEAR(tiny.report.studio->scale, 100, 1e-9);
  EXPECT_NEAR(boundsOf(objectNamed(tiny.scene, "tiny")).max.y, 1, 1e-12);
}

TEST(DefaultStudio, DuplicateVerticesAreWeldedAndCountedPerObject) {
  // Each face lists its own four corners (24 vertices for 8 corners): welded, the cube closed.
  std::ostringstream obj;
  obj << "o soup\n";
  const std::string box = boxObj(Vec3(0), Vec3(1), 1);
  std::vector<std::string> corners;
  std::istringstream lines(box);
  std::string line;
  int next = 1;
  std::string faces;
  while (std::getline(lines, line)) {
    if (line[0] == 'v') corners.push_back(line);
    if (line[0] != 'f') continue;
    std::istringstream words(line.substr(2));
    int index;
    faces += "f";
    while (words >> index) {
      obj << corners[size_t(index - 1)] << "\n";
      faces += " " + std::to_string(next++);
    }
    faces += "\n";
  }
  obj << faces << "o other\n" << boxObj(Vec3(2, 0, 0), Vec3(1), 25);
  const ImportResult result = importText(obj.str(), "soup.obj");
  EXPECT_EQ(factsOf(result.report, "soup").verticesWelded, 16u) << result.report.summary();
  EXPECT_EQ(factsOf(result.report, "soup").closedComponents, 1u);
  EXPECT_EQ(factsOf(result.report, "other").verticesWelded, 0u);
  EXPECT_EQ(result.report.repaired("duplicate_vertices_merged"), 16u);
  EXPECT_TRUE(consistentlyClosed(objectNamed(result.scene, "soup")));
}

TEST(DefaultStudio, NonManifoldEdgeIsReportedAndLeft) {
  // Three quads on one edge (a book's spine).
  const std::string obj =
      "o book\nv 0 0 0\nv 0 1 0\nv 1 0 0\nv 1 1 0\nv 0 0 1\nv 0 1 1\nv -1 0 0\nv -1 1 0\n"
      "f 1 3 4 2\nf 1 5 6 2\nf 2 8 7 1\n";
  const ImportResult result = importText(obj, "book.obj");
  EXPECT_EQ(result.report.repaired("non_manifold_edges"), 1u) << result.report.summary();
  EXPECT_EQ(factsOf(result.report, "book").nonManifoldEdges, 1u);
  EXPECT_EQ(factsOf(result.report, "book").components, 3u);
  EXPECT_EQ(objectNamed(result.scene, "book").faces.size(), 3u);
  bool warned = false;
  for (const std::string& warning : result.report.warnings)
    warned |=
        warning ==
        "non-manifold edges left as they are: 'book' has 1 edge shared by three or more faces";
  EXPECT_TRUE(warned) << result.report.summary();
}

TEST(DefaultStudio, NoStudioKeepsTheError) {
  ImportOptions options;
  options.studio = false;
  try {
    importText("o cube\n" + boxObj(Vec3(0), Vec3(1), 1), "cube.obj", options);
    FAIL() << "imported a scene without a light";
  } catch (const protocol::ValidationError& error) {
    EXPECT_NE(std::string(error.what()).find("no emissive faces"), std::string::npos)
        << error.what();
  }
}

TEST(DefaultStudio, LightRadianceIsTheStudioLights) {
  ImportOptions options;
  options.lightRadiance = Vec3(1, 2, 3);
  const ImportResult result =
      importText("o cube\n" + boxObj(Vec3(0), Vec3(1), 1), "cube.obj", options);
  ASSERT_EQ(result.scene.lights().size(), 1u);
  EXPECT_EQ(result.scene.lights()[0].radiance, Vec3(1, 2, 3));
}

TEST(DefaultStudio, AFileWithLightsIsNotPutInTheStudio) {
  const ImportResult result =
      importObjFile(testing::kData + "/cornell_mm.obj", ImportOptions{0.001, {}, true});
  EXPECT_FALSE(result.report.studio);
  EXPECT_FALSE(result.report.toJson().contains("studio"));
  EXPECT_EQ(result.scene.lights().size(), 1u);
  EXPECT_FALSE(result.scene.findObject("studio_floor"));
}

TEST(DefaultStudio, ClosedRoomAroundItsLightStaysInward) {
  // A room modelled as one closed box wound inward, one wall wound wrong, a lamp inside it.
  std::string obj = "mtllib room.mtl\no room\nusemtl white\n";
  std::string box = boxObj(Vec3(0), Vec3(4, 3, 4), 1, 4);
  // Reverse every face: inward (face 4 then is the odd one out).
  std::istringstream lines(box);
  std::string line;
  while (std::getline(lines, line)) {
    if (line[0] == 'f') {
      std::istringstream words(line.substr(2));
      std::vector<std::string> indices{std::istream_iterator<std::string>(words), {}};
      line = "f";
      for (auto it = indices.rbegin(); it != indices.rend(); ++it) line += " " + *it;
    }
    obj += line + "\n";
  }
  obj +=
      "o lamp\nusemtl lamp\nv 1.5 2.9 1.5\nv 2.5 2.9 1.5\nv 2.5 2.9 2.5\nv 1.5 2.9 2.5\nf 9 10 11 "
      "12\n";
  const ImportResult result = importObjText(
      obj, {{"room.mtl", "newmtl white\nKd 0.8 0.8 0.8\nnewmtl lamp\nKe 5 5 5\n"}}, {}, "room.obj");
  EXPECT_FALSE(result.report.studio);
  EXPECT_EQ(result.report.repaired("closed_components_facing_inward_around_lights"), 1u)
      << result.report.summary();
  EXPECT_EQ(result.report.repaired("faces_flipped_for_consistent_orientation"), 1u);
  const Object& room = objectNamed(result.scene, "room");
  EXPECT_TRUE(consistentlyClosed(room));
  EXPECT_NEAR(signedVolume(room), -48, 1e-9);
}

// Seeded: random boxes (one object each, some faces flipped, some corners listed twice) of random
// size go through the whole import; each comes back closed and outward, the flips counted.
TEST(DefaultStudio, SeededBoxesThroughTheImporterComeBackClosedAndOutward) {
  for (uint64_t seed = 1; seed <= 25; ++seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> size(0.05, 300), position(-1000, 1000);
    const int boxes = 1 + int(rng() % 4);
    const double unit = size(rng);
    std::string obj;
    size_t flips = 0;
    for (int b = 0; b < boxes; ++b) {
      const int flip = int(rng() % 8) - 2;  // -2, -1: none
      flips += flip >= 0;
      obj += "o box" + std::to_string(b) + "\n" +
             boxObj(Vec3(position(rng), position(rng), position(rng)) * (unit / 1000),
                    Vec3(unit * (0.2 + 0.8 * double(rng() % 100) / 100), unit * 0.5, unit),
                    1 + 8 * b, flip);
    }
    const ImportResult result = importText(obj, "boxes.obj");
    ASSERT_TRUE(result.report.studio) << "seed " << seed;
    EXPECT_EQ(result.report.repaired("faces_flipped_for_consistent_orientation"), flips)
        << "seed " << seed;
    Bounds all{Vec3(INFINITY), Vec3(-INFINITY)};
    for (int b = 0; b < boxes; ++b) {
      const Object& box = objectNamed(result.scene, "box" + std::to_string(b));
      EXPECT_TRUE(consistentlyClosed(box)) << "seed " << seed << " box " << b;
      EXPECT_GT(signedVolume(box), 0) << "seed " << seed << " box " << b;
      EXPECT_EQ(factsOf(result.report, box.id).closedComponents, 1u);
      const Bounds bb = boundsOf(box);
      all.min = glm::min(all.min, bb.min);
      all.max = glm::max(all.max, bb.max);
    }
    EXPECT_NEAR(all.min.y, 0, 1e-12) << "seed " << seed;
    const Vec3 extent = all.max - all.min;
    const double largest = std::max({extent.x, extent.y, extent.z});
    EXPECT_LE(largest, kStudioMaxFit + 1e-12) << "seed " << seed;
    EXPECT_GE(largest, kStudioMinFit - 1e-12) << "seed " << seed;
  }
}

TEST(DefaultStudio, CommandLineSaysSoAndNoStudioFails) {
  const auto dir = scratchDir();
  const std::string obj =
      writeFile(dir / "model.obj", "o cube\n" + boxObj(Vec3(0), Vec3(200), 1, 0));
  const std::string scene = (dir / "scene.json").string(), report = (dir / "report.json").string();
  ASSERT_EQ(
      runPenumbra("import " + obj + " --out " + scene + " --report " + report, dir / "import"), 0);
  std::ifstream err(dir / "import.err");
  const std::string stderrText{std::istreambuf_iterator<char>(err), {}};
  EXPECT_NE(stderrText.find("no lights in "), std::string::npos) << stderrText;
  EXPECT_NE(stderrText.find("placed it in the default studio"), std::string::npos) << stderrText;
  EXPECT_NE(stderrText.find("'cube': 6 faces, 1 component, 1 closed; 1 face flipped"),
            std::string::npos)
      << stderrText;
  const nlohmann::json reportJson = nlohmann::json::parse(std::ifstream(report));
  EXPECT_EQ(reportJson["studio"]["scale"], 0.005);
  EXPECT_EQ(reportJson["meshes"][0]["faces_flipped"], 1);
  EXPECT_NO_THROW(protocol::loadSceneFile(scene));
  // The built scene has lit faces (the studio's light reaches the model and the floor).
  ASSERT_EQ(runPenumbra("build " + scene + " --out " + (dir / "mesh.json").string(), dir / "build"),
            0);

  EXPECT_EQ(runPenumbra("import " + obj + " --out " + scene + ".2 --no-studio", dir / "refused"),
            2);
  std::ifstream refused(dir / "refused.err");
  const std::string refusedText{std::istreambuf_iterator<char>(refused), {}};
  EXPECT_NE(refusedText.find("no emissive faces"), std::string::npos) << refusedText;
}

}  // namespace
}  // namespace penumbra::interchange
