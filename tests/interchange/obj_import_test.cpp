// OBJ import: a scene written out as OBJ by the test comes back with the same
// faces and light; messy files are repaired, and every repair is counted.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <tuple>
#include <sstream>

#include "core/geom/polygon.h"
#include "interchange/obj_import.h"
#include "interchange/scene_import.h"
#include "interchange_fixtures.h"
#include "protocol/scene_json.h"

namespace penumbra::interchange {
namespace {

using testing::kData;
using testing::scratchDir;
using testing::writeFile;

// The scene as OBJ + MTL: one 'o' per object with its world vertices, a material
// per object material, and the lights as emissive ('Ke') quads.
void writeObj(const Scene& scene, const std::filesystem::path& obj, const std::filesystem::path& mtl) {
  std::ostringstream o, m;
  o.precision(17);
  m.precision(17);
  o << "# written by obj_import_test\nmtllib " << mtl.filename().string() << "\n";
  for (const Material& material : scene.materials())
    m << "newmtl " << material.id << "\nKd " << material.albedo.x << " " << material.albedo.y << " "
      << material.albedo.z << "\n";
  int next = 1;
  for (size_t i = 0; i < scene.lights().size(); ++i) {
    const Light& light = scene.lights()[i];
    m << "newmtl emit_" << light.id << "\nKe " << light.radiance.x << " " << light.radiance.y << " "
      << light.radiance.z << "\n";
    o << "o " << light.id << "\nusemtl emit_" << light.id << "\n";
    for (const Vec3& p : light.polygon) o << "v " << p.x << " " << p.y << " " << p.z << "\n";
    o << "f";
    for (size_t k = 0; k < light.polygon.size(); ++k) o << " " << next++;
    o << "\n";
  }
  for (size_t i = 0; i < scene.objects().size(); ++i) {
    const Object& object = scene.objects()[i];
    o << "o " << object.id << "\n";
    if (!object.material.empty()) o << "usemtl " << object.material << "\n";
    // Each world position once per object, as modelling tools write shared corners.
    std::map<std::tuple<double, double, double>, int> indexOf;
    const std::vector<Polygon3> faces = Scene::worldPolygons(object);
    for (const Polygon3& face : faces) {
      for (const Vec3& p : face)
        if (indexOf.emplace(std::tuple{p.x, p.y, p.z}, next).second) {
          o << "v " << p.x << " " << p.y << " " << p.z << "\n";
          ++next;
        }
      o << "f";
      for (const Vec3& p : face) o << " " << indexOf.at({p.x, p.y, p.z});
      o << "\n";
    }
  }
  writeFile(obj, o.str());
  writeFile(mtl, m.str());
}

void expectSamePolygon(const Polygon3& actual, const Polygon3& expected, double eps) {
  ASSERT_EQ(actual.size(), expected.size());
  // Same cycle, any starting vertex.
  const auto start = std::min_element(actual.begin(), actual.end(), [&](const Vec3& a, const Vec3& b) {
    return glm::length(a - expected[0]) < glm::length(b - expected[0]);
  });
  const size_t offset = size_t(start - actual.begin());
  for (size_t k = 0; k < expected.size(); ++k)
    EXPECT_LE(glm::length(actual[(offset + k) % actual.size()] - expected[k]), eps) << "vertex " << k;
}

TEST(ObjImport, RoundTripGivesTheSameFacesLightsAndAlbedos) {
  const auto dir = scratchDir();
  const Scene original = protocol::loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json");
  writeObj(original, dir / "cornell.obj", dir / "cornell.mtl");
  const ImportResult result = importObjFile((dir / "cornell.obj").string(), {});
  // Nothing repaired; the two blocks' bottoms lie on the floor, back to back with it: reported, kept.
  EXPECT_EQ(result.report.repairs, (std::map<std::string, size_t>{{"coplanar_overlapping_face_pairs", 2}}))
      << result.report.summary();

  const Scene& imported = result.scene;
  ASSERT_EQ(imported.lights().size(), original.lights().size());
  for (size_t i = 0; i < original.lights().size(); ++i) {
    expectSamePolygon(imported.lights()[i].polygon, original.lights()[i].polygon, 0);
    EXPECT_EQ(imported.lights()[i].radiance, original.lights()[i].radiance);
    EXPECT_EQ(imported.lights()[i].id, original.lights()[i].id);
  }
  ASSERT_EQ(imported.objects().size(), original.objects().size());
  ASSERT_EQ(imported.faces().size(), original.faces().size());
  for (size_t f = 0; f < original.faces().size(); ++f) {
    expectSamePolygon(imported.faces()[f].polygon, original.faces()[f].polygon, 0);
    EXPECT_EQ(imported.albedo(imported.faces()[f].id), original.albedo(original.faces()[f].id)) << "face " << f;
  }
  for (size_t i = 0; i < original.objects().size(); ++i)
    EXPECT_EQ(imported.objects()[i].id, original.objects()[i].id);
  // What the importer wrote is what it validated.
  EXPECT_EQ(protocol::sceneToJson(protocol::sceneFromJson(result.sceneJson)), protocol::sceneToJson(imported));
}

// A floor, a box on it and a light, in OBJ text; `extra` goes before the light.
std::string smallScene(const std::string& extra) {
  return "mtllib small.mtl\n"
         "o floor\nusemtl grey\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nf 1 2 3 4\n" + extra +
         "o lamp\nusemtl lamp\nv -0.5 3 -0.5\nv 0.5 3 -0.5\nv 0.5 3 0.5\nv -0.5 3 0.5\nf -4 -3 -2 -1\n";
}
const std::string kSmallMtl = "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 5 5\n";

TEST(ObjImport, CrlfCommentsAndBlankLinesAreRead) {
  const auto dir = scratchDir();
  std::string text = "# a comment\n\n" + smallScene("# another comment\n");
  std::string crlf;
  for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  writeFile(dir / "small.obj", crlf);
  writeFile(dir / "small.mtl", kSmallMtl);
  const ImportResult result = importObjFile((dir / "small.obj").string(), {});
  EXPECT_EQ(result.report.repaired("crlf_line_endings_read"), size_t(std::count(crlf.begin(), crlf.end(), '\r')));
  ASSERT_EQ(result.scene.lights().size(), 1u);
  EXPECT_EQ(result.scene.lights()[0].radiance, Vec3(5.0));
  ASSERT_EQ(result.scene.objects().size(), 1u);
  EXPECT_EQ(result.scene.objects()[0].id, "floor");  // no '\r' left in names
  EXPECT_EQ(result.scene.objects()[0].material, "grey");
}

TEST(ObjImport, MissingMtlFileIsCountedAndLightRadianceCanStandIn) {
  const auto dir = scratchDir();
  writeFile(dir / "small.obj", smallScene(""));
  // No small.mtl: without a radiance there is no light; kept out of the default studio, the
  // error says what to do.
  ImportOptions noStudio;
  noStudio.studio = false;
  try {
    importObjFile((dir / "small.obj").string(), noStudio);
    FAIL() << "imported a scene without a light";
  } catch (const protocol::ValidationError& error) {
    EXPECT_NE(std::string(error.what()).find("--light-radiance"), std::string::npos) << error.what();
  }
  ImportOptions options;
  options.lightRadiance = Vec3(2, 3, 4);
  const ImportResult result = importObjFile((dir / "small.obj").string(), options);
  EXPECT_EQ(result.report.repaired("missing_material_files"), 1u);
  EXPECT_EQ(result.report.repaired("undefined_materials"), 2u);
  EXPECT_EQ(result.report.repaired("light_radiance_overridden"), 1u);
  ASSERT_EQ(result.scene.lights().size(), 1u);
  EXPECT_EQ(result.scene.lights()[0].radiance, Vec3(2, 3, 4));
  EXPECT_TRUE(result.scene.objects()[0].material.empty());  // the default albedo
}

TEST(ObjImport, DuplicateVerticesAreMergedAndDuplicateFacesDropped) {
  const auto dir = scratchDir();
  // A quad whose corners are listed twice; the face uses both copies, and again.
  writeFile(dir / "small.obj", smallScene("o slab\nusemtl grey\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"
                                          "v 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\nf -8 -1 -2 -3\nf -4 -5 -6 -7\n"));
  writeFile(dir / "small.mtl", kSmallMtl);
  const ImportResult result = importObjFile((dir / "small.obj").string(), {});
  EXPECT_EQ(result.report.repaired("duplicate_vertices_merged"), 4u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("duplicate_faces_dropped"), 1u);
  const auto slab = result.scene.findObject("slab");
  ASSERT_TRUE(slab);
  EXPECT_EQ(result.scene.objects()[*slab].vertices.size(), 4u);
  EXPECT_EQ(result.scene.objects()[*slab].faces.size(), 1u);
}

TEST(ObjImport, NonConvexAndNonPlanarQuadsAreSplitNotRefused) {
  const auto dir = scratchDir();
  writeFile(dir / "small.obj",
            smallScene("o dart\nusemtl grey\nv 0 1 0\nv 0 1 1\nv 0.3 1 0.3\nv 1 1 0\nf -4 -3 -2 -1\n"
                       "o warped\nusemtl grey\nv -1 1 -1\nv -1 1.2 0\nv 0 1 0\nv 0 1 -1\nf -4 -3 -2 -1\n"));
  writeFile(dir / "small.mtl", kSmallMtl);
  const ImportResult result = importObjFile((dir / "small.obj").string(), {});
  EXPECT_EQ(result.report.repaired("non_convex_polygons_split"), 1u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("non_planar_polygons_split"), 1u);
  EXPECT_EQ(result.report.repaired("pieces_added_by_splits"), 2u);
  EXPECT_EQ(result.scene.objects()[*result.scene.findObject("dart")].faces.size(), 2u);
  EXPECT_EQ(result.scene.objects()[*result.scene.findObject("warped")].faces.size(), 2u);
}

TEST(ObjImport, ReverseWoundCoplanarDuplicatesStayAsTwoSidedSurface) {
  const auto dir = scratchDir();
  writeFile(dir / "small.obj", smallScene("o shelf\nusemtl grey\nv -1 1 -1\nv -1 1 1\nv 1 1 1\nv 1 1 -1\n"
                                          "f -4 -3 -2 -1\nf -1 -2 -3 -4\n"));
  writeFile(dir / "small.mtl", kSmallMtl);
  const ImportResult result = importObjFile((dir / "small.obj").string(), {});
  EXPECT_EQ(result.report.repaired("reverse_wound_duplicates_kept_two_sided"), 1u) << result.report.summary();
  const Object& shelf = result.scene.objects()[*result.scene.findObject("shelf")];
  ASSERT_EQ(shelf.faces.size(), 2u);
  EXPECT_EQ(shelf.vertices.size(), 4u);
}

TEST(ObjImport, GroupsWithSeveralMaterialsBecomeOneObjectEach) {
  const auto dir = scratchDir();
  writeFile(dir / "small.obj", smallScene("g pair\nusemtl grey\nv 0 1 0\nv 0 1 1\nv 1 1 1\nv 1 1 0\nf -4 -3 -2 -1\n"
                                          "usemtl other\nv 0 2 0\nv 0 2 1\nv 1 2 1\nv 1 2 0\nf -4 -3 -2 -1\n"));
  writeFile(dir / "small.mtl", kSmallMtl + "newmtl other\nKd 2 0.5 -1\n");
  const ImportResult result = importObjFile((dir / "small.obj").string(), {});
  EXPECT_EQ(result.report.repaired("groups_split_by_material"), 1u);
  EXPECT_EQ(result.report.repaired("albedo_clamped_to_0_1"), 1u);
  ASSERT_TRUE(result.scene.findObject("pair.grey"));
  ASSERT_TRUE(result.scene.findObject("pair.other"));
  EXPECT_EQ(result.scene.albedo({result.scene.handleOf(*result.scene.findObject("pair.other")), 0}), Vec3(1, 0.5, 0));
}

TEST(ObjImport, WilliamsStyleCornellBoxTakesTheLightFromKaAndTurnsItDown) {
  const ImportResult result = importSceneFile(kData + "/williams_style.obj", {});
  const ImportReport& report = result.report;
  EXPECT_EQ(report.repaired("light_radiance_taken_from_ka"), 1u) << report.summary();
  EXPECT_EQ(report.repaired("lights_turned_to_face_the_scene"), 1u);
  EXPECT_EQ(report.repaired("duplicate_vertices_merged"), 8u);
  EXPECT_GT(report.repaired("crlf_line_endings_read"), 50u);
  ASSERT_EQ(result.scene.lights().size(), 1u);
  const Light& light = result.scene.lights()[0];
  EXPECT_EQ(light.radiance, Vec3(0.78));
  EXPECT_LT(light.plane().normal.y, -0.999);  // emits downwards, into the box
  for (const Vec3& p : light.polygon) EXPECT_EQ(p.y, 1.98);
  EXPECT_EQ(result.scene.objects().size(), 6u);
  EXPECT_EQ(result.scene.objects()[*result.scene.findObject("shortBox")].vertices.size(), 8u);
  EXPECT_EQ(report.toJson()["repairs"]["light_radiance_taken_from_ka"], 1);
  // The box's bottom lies on the floor, back to back with it: kept, counted and named.
  EXPECT_EQ(report.repaired("coplanar_overlapping_face_pairs"), 1u);
  EXPECT_EQ(report.repaired("covered_coplanar_faces_dropped"), 0u);
  EXPECT_NE(std::find(report.warnings.begin(), report.warnings.end(),
                      "coplanar faces overlap: 'floor' face 0 and 'shortBox' face 4 lie in one plane back to back "
                      "and share an area of 0.25; both kept"),
            report.warnings.end())
      << report.summary();
}

TEST(ObjImport, BadInputIsAClearErrorNotACrash) {
  const auto dir = scratchDir();
  writeFile(dir / "bad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nf 1 2 7\n");
  EXPECT_THROW(importObjFile((dir / "bad.obj").string(), {}), protocol::ValidationError);
  writeFile(dir / "empty.obj", "# nothing\n");
  EXPECT_THROW(importObjFile((dir / "empty.obj").string(), {}), protocol::ValidationError);
  EXPECT_THROW(importObjFile((dir / "absent.obj").string(), {}), std::runtime_error);
  EXPECT_THROW(importSceneFile((dir / "scene.fbx").string(), {}), protocol::ValidationError);
  ImportOptions badScale;
  badScale.scale = -1;
  writeFile(dir / "small.obj", smallScene(""));
  writeFile(dir / "small.mtl", kSmallMtl);
  EXPECT_THROW(importObjFile((dir / "small.obj").string(), badScale), protocol::ValidationError);
}

// Names come from the file's bytes: invalid UTF-8 in them is replaced (U+FFFD) and counted,
// so the scene and the report are valid JSON (a fuzz finding: the report's dump() threw).
TEST(ObjImport, InvalidUtf8InNamesIsReplacedAndCounted) {
  const std::string obj = "mtllib m\xff.mtl\n"
                          "o fl\xc0\xafoor\nusemtl gr\xed" "ey\nv -2 0 -2\nv -2 0 2\nv 2 0 2\nv 2 0 -2\nf 1 2 3 4\n"
                          "o lamp\nusemtl lamp\nv -0.5 3 -0.5\nv 0.5 3 -0.5\nv 0.5 3 0.5\nv -0.5 3 0.5\nf -4 -3 -2 -1\n";
  const std::string mtl = "newmtl gr\xed" "ey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 5 5\n";
  const ImportResult result = importObjText(obj, {{"m\xff.mtl", mtl}}, {}, "sc\xfe" "ne.obj");
  EXPECT_NO_THROW((void)result.sceneJson.dump());
  EXPECT_NO_THROW((void)result.report.toJson().dump());
  EXPECT_EQ(result.sceneJson["objects"][0]["id"], "fl\uFFFD\uFFFDoor");
  EXPECT_EQ(result.sceneJson["objects"][0]["material"], "gr\uFFFDey");
  EXPECT_TRUE(result.sceneJson["materials"].contains("gr\uFFFDey"));
  EXPECT_EQ(result.report.repairs.at("names_with_invalid_utf8_replaced"), 2);
  EXPECT_EQ(result.report.toJson()["source"], "sc\uFFFDne.obj");
}

TEST(ObjImport, FromMemoryMatchesFromFile) {
  const auto dir = scratchDir();
  writeFile(dir / "small.obj", smallScene(""));
  writeFile(dir / "small.mtl", kSmallMtl);
  const ImportResult fromFile = importObjFile((dir / "small.obj").string(), {});
  const std::string text = smallScene("");
  const ImportResult fromMemory =
      importSceneBytes(std::vector<uint8_t>(text.begin(), text.end()), "small.obj", {{"small.mtl", kSmallMtl}}, {});
  EXPECT_EQ(fromMemory.sceneJson, fromFile.sceneJson);
}

}  // namespace
}  // namespace penumbra::interchange

namespace penumbra::interchange {
namespace {

// MTL's PBR extension (Pm, Pr), transparency (d) with Ni, and Ns onto material types.
TEST(ObjImport, MtlParametersMapOntoMicrofacetTypes) {
  const std::string mtl =
      "newmtl metal\nKd 0.9 0.6 0.3\nPm 1\nPr 0.5\n"
      "newmtl glass\nKd 1 1 1\nd 0.2\nNi 1.33\nNs 98\n"
      "newmtl paint\nKd 0.5 0.5 0.5\nNs 250\n"
      "newmtl light\nKe 5 5 5\n";
  std::string obj = "mtllib m.mtl\n";
  const char* names[] = {"metal", "glass", "paint", "light"};
  for (int i = 0; i < 4; ++i) {
    obj += "o " + std::string(names[i]) + "\nusemtl " + names[i] + "\n";
    for (const char* corner : {"-1 %d -1", "-1 %d 1", "1 %d 1", "1 %d -1"}) {
      char line[64];
      std::snprintf(line, sizeof line, corner, i);
      obj += "v " + std::string(line) + "\n";
    }
    const int b = 4 * i + 1;
    // the light (top) faces down towards the others
    obj += i == 3 ? "f " + std::to_string(b) + " " + std::to_string(b + 3) + " " + std::to_string(b + 2) + " " +
                        std::to_string(b + 1) + "\n"
                  : "f " + std::to_string(b) + " " + std::to_string(b + 1) + " " + std::to_string(b + 2) + " " +
                        std::to_string(b + 3) + "\n";
  }
  const ImportResult result = importObjText(obj, {{"m.mtl", mtl}}, {}, "m.obj");
  const Scene& scene = result.scene;
  const Material& metal = scene.materials()[*scene.findMaterial("metal")];
  EXPECT_EQ(metal.type, MaterialType::Conductor);
  EXPECT_DOUBLE_EQ(metal.roughness.x, 0.25);
  const Material& glass = scene.materials()[*scene.findMaterial("glass")];
  EXPECT_EQ(glass.type, MaterialType::Dielectric);
  EXPECT_DOUBLE_EQ(glass.ior, 1.33);
  EXPECT_NEAR(glass.roughness.x, std::sqrt(2.0 / 100.0), 1e-12);
  EXPECT_EQ(scene.materials()[*scene.findMaterial("paint")].type, MaterialType::Diffuse);
  EXPECT_EQ(result.report.repaired("materials_mapped_to_conductor"), 1u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("materials_mapped_to_dielectric"), 1u);
}

}  // namespace
}  // namespace penumbra::interchange

namespace penumbra::interchange {
namespace {

// The rules' edges: a Pm metal's F0 is its Kd; Ns gives α without Pr; Pm below a half stays
// diffuse; Tr is transparency too; an Ni missing or out of (1, 4] is 1.5; neither Pr nor Ns: α 0.5.
TEST(ObjImport, MtlMappingEdges) {
  const std::string mtl =
      "newmtl metal_ns\nKd 0.9 0.6 0.3\nPm 1\nNs 48\n"
      "newmtl half\nKd 0.5 0.5 0.5\nPm 0.3\nPr 0.2\n"
      "newmtl tr_glass\nKd 1 1 1\nTr 0.9\n"
      "newmtl bad_ni\nKd 1 1 1\nd 0.5\nNi 7\n"
      "newmtl plain_metal\nKd 0.7 0.7 0.7\nPm 0.9\n"
      "newmtl light\nKe 5 5 5\n";
  const std::vector<std::string> names = {"metal_ns", "half", "tr_glass", "bad_ni", "plain_metal", "light"};
  std::string obj = "mtllib m.mtl\n";
  for (size_t i = 0; i < names.size(); ++i) {
    obj += "o " + names[i] + "\nusemtl " + names[i] + "\n";
    for (const char* corner : {"-1 %d -1", "-1 %d 1", "1 %d 1", "1 %d -1"}) {
      char line[64];
      std::snprintf(line, sizeof line, corner, int(i));
      obj += "v " + std::string(line) + "\n";
    }
    const int b = 4 * int(i) + 1;
    const bool top = i + 1 == names.size();  // the light faces down towards the others
    obj += "f " + std::to_string(b) + " " + std::to_string(top ? b + 3 : b + 1) + " " + std::to_string(b + 2) + " " +
           std::to_string(top ? b + 1 : b + 3) + "\n";
  }
  const ImportResult result = importObjText(obj, {{"m.mtl", mtl}}, {}, "m.obj");
  const Scene& scene = result.scene;
  auto material = [&](const std::string& name) { return scene.materials()[*scene.findMaterial(name)]; };
  const Material metal = material("metal_ns");
  EXPECT_EQ(metal.type, MaterialType::Conductor);
  EXPECT_NEAR(metal.roughness.x, std::sqrt(2.0 / 50.0), 1e-12);
  const Vec3 kd(0.9, 0.6, 0.3);
  for (int c = 0; c < 3; ++c)  // normal-incidence reflectance of eta + ik is Kd
    EXPECT_NEAR((std::pow(metal.eta[c] - 1, 2) + metal.k[c] * metal.k[c]) /
                    (std::pow(metal.eta[c] + 1, 2) + metal.k[c] * metal.k[c]),
                kd[c], 1e-6);
  EXPECT_EQ(material("half").type, MaterialType::Diffuse);
  EXPECT_EQ(material("tr_glass").type, MaterialType::Dielectric);
  EXPECT_DOUBLE_EQ(material("tr_glass").ior, 1.5);
  EXPECT_DOUBLE_EQ(material("bad_ni").ior, 1.5);
  EXPECT_EQ(material("plain_metal").type, MaterialType::Conductor);
  EXPECT_DOUBLE_EQ(material("plain_metal").roughness.x, 0.5);
  EXPECT_EQ(result.report.repaired("materials_mapped_to_conductor"), 2u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("materials_mapped_to_dielectric"), 2u);
}

}  // namespace
}  // namespace penumbra::interchange
