// Every refusal of the scene reader: a valid base scene, one small mutation per
// case, and the exact key path plus a word of the message that must come back.
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "protocol/scene_json.h"
#include "scene_fixtures.h"

namespace penumbra::protocol {
namespace {

using nlohmann::json;
using testing::baseSceneJson;

struct MalformedCase {
  const char* name;
  std::function<void(json&)> mutate;
  const char* path;
  const char* word;  // must appear in problem()
};

// A quad on y = 0 whose corner 2 is lifted by `lift` (relative to a size of ~8.5).
json liftedFloor(double lift) {
  return json::parse("[[-3, 0, -3], [-3, 0, 3], [3, " + std::to_string(lift) + ", 3], [3, 0, -3]]");
}

// Corner normals for the cube of objects[1]: six faces of four corners, all straight up.
json cubeCornerNormals() {
  json lists = json::array();
  for (int f = 0; f < 6; ++f) lists.push_back(json::array({{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 1, 0}}));
  return lists;
}

const std::vector<MalformedCase>& sceneCases() {
  static const std::vector<MalformedCase> all = {
      // Document root and header.
      {"RootNotObject", [](json& s) { s = json::array({s}); }, "", "expected an object"},
      {"MissingFormat", [](json& s) { s.erase("format"); }, "format", "missing required key"},
      {"WrongFormat", [](json& s) { s["format"] = "penumbra.mesh"; }, "format", "penumbra.scene"},
      {"FormatNotString", [](json& s) { s["format"] = 1; }, "format", "expected a string"},
      {"MissingVersion", [](json& s) { s.erase("version"); }, "version", "missing required key"},
      {"WrongVersion", [](json& s) { s["version"] = 2; }, "version", "unsupported version 2"},
      {"VersionAsString", [](json& s) { s["version"] = "1"; }, "version", "expected a number"},
      // Lights.
      {"MissingLights", [](json& s) { s.erase("lights"); }, "lights", "missing required key"},
      {"LightsNotArray", [](json& s) { s["lights"] = json::object(); }, "lights", "expected an array"},
      {"EmptyLights", [](json& s) { s["lights"] = json::array(); }, "lights", "at least one light"},
      {"LightNotObject", [](json& s) { s["lights"][0] = 3; }, "lights[0]", "expected an object"},
      {"LightMissingId", [](json& s) { s["lights"][0].erase("id"); }, "lights[0].id", "missing required key"},
      {"LightIdNotString", [](json& s) { s["lights"][0]["id"] = 7; }, "lights[0].id", "expected a string"},
      {"LightIdEmpty", [](json& s) { s["lights"][0]["id"] = ""; }, "lights[0].id", "non-empty"},
      {"DuplicateLightId", [](json& s) { s["lights"].push_back(s["lights"][0]); }, "lights[1].id",
       "duplicate light id 'lamp'"},
      {"LightMissingPolygon", [](json& s) { s["lights"][0].erase("polygon"); }, "lights[0].polygon",
       "missing required key"},
      {"LightTwoVertices", [](json& s) { s["lights"][0]["polygon"].erase(0); s["lights"][0]["polygon"].erase(0); },
       "lights[0].polygon", "at least 3 vertices"},
      {"LightNotPlanar", [](json& s) { s["lights"][0]["polygon"][2][1] = 2.9; }, "lights[0].polygon", "not planar"},
      {"LightNotConvex",
       [](json& s) {  // a dent pushed into the square's middle
         s["lights"][0]["polygon"].insert(s["lights"][0]["polygon"].begin() + 2, json::array({0.0, 2.99, 0.0}));
       },
       "lights[0].polygon", "not convex"},
      {"LightPentagram",  // every corner turns the same way, but twice around
       [](json& s) {
         json star = json::array();
         for (int k = 0; k < 5; ++k) {
           const double a = 2 * M_PI * double((2 * k) % 5) / 5;
           star.push_back(json::array({std::cos(a), 2.99, -std::sin(a)}));
         }
         s["lights"][0]["polygon"] = star;
       },
       "lights[0].polygon", "not convex"},
      {"LightCollinear", [](json& s) { s["lights"][0]["polygon"] = json::parse("[[0,3,0],[1,3,0],[2,3,0]]"); },
       "lights[0].polygon", "degenerate"},
      {"LightVertexTwoNumbers", [](json& s) { s["lights"][0]["polygon"][1] = json::array({1, 2}); },
       "lights[0].polygon[1]", "3 numbers"},
      {"LightVertexComponentString", [](json& s) { s["lights"][0]["polygon"][1][2] = "0.5"; },
       "lights[0].polygon[1][2]", "expected a number"},
      {"LightMissingRadiance", [](json& s) { s["lights"][0].erase("radiance"); }, "lights[0].radiance",
       "missing required key"},
      {"NegativeRadiance", [](json& s) { s["lights"][0]["radiance"][1] = -0.5; }, "lights[0].radiance", "negative"},
      {"InfiniteRadiance",
       [](json& s) { s["lights"][0]["radiance"][0] = std::numeric_limits<double>::infinity(); },
       "lights[0].radiance[0]", "not finite"},
      // Materials.
      {"MaterialsNotObject", [](json& s) { s["materials"] = json::array(); }, "materials", "expected an object"},
      {"MaterialMissingAlbedo", [](json& s) { s["materials"]["red"].erase("albedo"); }, "materials.red.albedo",
       "missing required key"},
      {"AlbedoAboveOne", [](json& s) { s["materials"]["red"]["albedo"][0] = 1.5; }, "materials.red.albedo",
       "outside [0, 1]"},
      {"AlbedoNegative", [](json& s) { s["materials"]["white"]["albedo"][2] = -0.1; }, "materials.white.albedo",
       "outside [0, 1]"},
      {"MaterialNameQuotedInPath",
       [](json& s) { s["materials"]["dark grey"] = {{"albedo", "grey"}}; }, "materials[\"dark grey\"].albedo",
       "3 numbers"},
      {"MaterialsMissingButNamed", [](json& s) { s.erase("materials"); }, "objects[0].material",
       "unknown material 'white'"},
      {"UnknownMaterial", [](json& s) { s["objects"][1]["material"] = "gold"; }, "objects[1].material",
       "unknown material 'gold'"},
      {"MaterialNotString", [](json& s) { s["objects"][1]["material"] = json::array(); }, "objects[1].material",
       "expected a string"},
      // Objects.
      {"MissingObjects", [](json& s) { s.erase("objects"); }, "objects", "missing required key"},
      {"ObjectsNotArray", [](json& s) { s["objects"] = "all"; }, "objects", "expected an array"},
      {"ObjectMissingId", [](json& s) { s["objects"][1].erase("id"); }, "objects[1].id", "missing required key"},
      // Corner normals (smooth shading): one list per face, one finite non-zero vector per corner.
      {"NormalsNotArray", [](json& s) { s["objects"][1]["normals"] = 1; }, "objects[1].normals", "expected an array"},
      {"NormalsTooFewFaces", [](json& s) { s["objects"][1]["normals"] = json::array({json::array()}); },
       "objects[1].normals", "lists of corner normals for 6 faces"},
      {"NormalsTooFewCorners",
       [](json& s) {
         s["objects"][1]["normals"] = cubeCornerNormals();
         s["objects"][1]["normals"][3].erase(0);
       },
       "objects[1].normals[3]", "4 corners but 3 normals"},
      {"NormalZero",
       [](json& s) {
         s["objects"][1]["normals"] = cubeCornerNormals();
         s["objects"][1]["normals"][2][1] = json::array({0, 0, 0});
       },
       "objects[1].normals[2][1]", "finite, non-zero"},
      {"NormalNotVector",
       [](json& s) {
         s["objects"][1]["normals"] = cubeCornerNormals();
         s["objects"][1]["normals"][5][3] = "up";
       },
       "objects[1].normals[5][3]", "expected"},
      {"DuplicateObjectId", [](json& s) { s["objects"][2]["id"] = "box1"; }, "objects[2].id",
       "duplicate object id 'box1'"},
      {"ObjectMissingVertices", [](json& s) { s["objects"][1].erase("vertices"); }, "objects[1].vertices",
       "missing required key"},
      {"ObjectMissingFaces", [](json& s) { s["objects"][1].erase("faces"); }, "objects[1].faces",
       "missing required key"},
      {"VertexNotArray", [](json& s) { s["objects"][1]["vertices"][3] = 0.5; }, "objects[1].vertices[3]",
       "3 numbers"},
      {"VertexNotFinite",
       [](json& s) { s["objects"][0]["vertices"][0][1] = std::numeric_limits<double>::quiet_NaN(); },
       "objects[0].vertices[0][1]", "not finite"},
      {"FaceNotArray", [](json& s) { s["objects"][1]["faces"][0] = 4; }, "objects[1].faces[0]", "expected an array"},
      {"FaceIndexOutOfRange", [](json& s) { s["objects"][1]["faces"][2][1] = 8; }, "objects[1].faces[2][1]",
       "out of range"},
      {"FaceIndexNegative", [](json& s) { s["objects"][1]["faces"][2][1] = -1; }, "objects[1].faces[2][1]",
       "out of range"},
      {"FaceIndexFractional", [](json& s) { s["objects"][1]["faces"][2][1] = 1.5; }, "objects[1].faces[2][1]",
       "not an integer"},
      {"FaceIndexString", [](json& s) { s["objects"][1]["faces"][2][1] = "4"; }, "objects[1].faces[2][1]",
       "expected an index"},
      {"FaceTwoVertices", [](json& s) { s["objects"][1]["faces"][0] = json::array({0, 1}); }, "objects[1].faces[0]",
       "at least 3 vertices"},
      {"FaceRepeatsVertex", [](json& s) { s["objects"][1]["faces"][4] = json::array({0, 1, 5, 1}); },
       "objects[1].faces[4]", "repeats vertex 1"},
      {"FaceNotPlanar", [](json& s) { s["objects"][0]["vertices"] = liftedFloor(1e-3); }, "objects[0].faces[0]",
       "not planar (off by"},
      {"FaceNotConvex",  // a dent in the floor's far edge
       [](json& s) {
         s["objects"][0]["vertices"].push_back(json::array({0, 0, 2}));
         s["objects"][0]["faces"][0] = json::array({0, 1, 4, 2, 3});
       },
       "objects[0].faces[0]", "not convex"},
      {"FaceSelfOverlapping",  // bow-tie: the two halves cancel, no plane
       [](json& s) { s["objects"][0]["faces"][0] = json::array({0, 2, 1, 3}); }, "objects[0].faces[0]",
       "degenerate"},
      {"FaceCollinear",
       [](json& s) {
         s["objects"][0]["vertices"] = json::parse("[[0,0,0],[1,0,0],[2,0,0],[3,0,0]]");
       },
       "objects[0].faces[0]", "degenerate"},
      {"StaticNotBool", [](json& s) { s["objects"][0]["static"] = "yes"; }, "objects[0].static", "true or false"},
      {"TransformNotObject", [](json& s) { s["objects"][1]["transform"] = json::array(); }, "objects[1].transform",
       "expected an object"},
      {"ZeroScale", [](json& s) { s["objects"][1]["transform"]["scale"][1] = 0; }, "objects[1].transform.scale",
       "zero"},
      {"RotateTwoNumbers", [](json& s) { s["objects"][1]["transform"]["rotate_deg"] = json::array({0, 30}); },
       "objects[1].transform.rotate_deg", "3 numbers"},
      {"ScaleFlattensFace", [](json& s) { s["objects"][1]["transform"]["scale"] = json::array({1e-300, 1, 1}); },
       "objects[1].faces[0]", "degenerate under the object's transform"},
      // Camera.
      {"CameraNotObject", [](json& s) { s["camera"] = true; }, "camera", "expected an object"},
      {"CameraMissingPosition", [](json& s) { s["camera"].erase("position"); }, "camera.position",
       "missing required key"},
      {"UnknownProjection", [](json& s) { s["camera"]["projection"] = "fisheye"; }, "camera.projection",
       "unknown projection 'fisheye'"},
      {"FovZero", [](json& s) { s["camera"]["fov_y_deg"] = 0; }, "camera.fov_y_deg", "outside [0.01, 179]"},
      {"Fov180", [](json& s) { s["camera"]["fov_y_deg"] = 180; }, "camera.fov_y_deg", "outside [0.01, 179]"},
      {"FovTiny", [](json& s) { s["camera"]["fov_y_deg"] = 1e-300; }, "camera.fov_y_deg", "outside [0.01, 179]"},
      {"NearZero", [](json& s) { s["camera"]["near"] = 0; }, "camera.near", "positive"},
      {"FarBelowNear", [](json& s) { s["camera"]["far"] = 0.05; }, "camera.far", "greater than near"},
      {"FarEqualsNear", [](json& s) { s["camera"]["far"] = 0.1; }, "camera.far", "greater than near"},
      {"TargetAtPosition", [](json& s) { s["camera"]["target"] = s["camera"]["position"]; }, "camera.target",
       "at the camera position"},
      {"UpParallelToView",
       [](json& s) { s["camera"]["up"] = json::array({0, -0.5, -6}); },  // position - target, scaled
       "camera.up", "parallel"},
      {"UpZero", [](json& s) { s["camera"]["up"] = json::array({0, 0, 0}); }, "camera.up", "parallel"},
      {"OrthographicHeightZero",
       [](json& s) { s["camera"]["projection"] = "orthographic"; s["camera"]["height"] = 0; }, "camera.height",
       "outside"},
      // Issue 36's classes: magnitudes that made Embree's ray assertion abort the server.
      {"OrthographicHeightHuge",
       [](json& s) { s["camera"]["projection"] = "orthographic"; s["camera"]["height"] = 1e300; }, "camera.height",
       "outside"},
      {"NearTiny", [](json& s) { s["camera"]["near"] = 1e-12; s["camera"]["far"] = 1e-6; }, "camera.near", "below"},
      {"FarOverNearTooLarge", [](json& s) { s["camera"]["near"] = 1e-3; s["camera"]["far"] = 1e5; }, "camera.near",
       "far / near"},
      {"FarBeyondTheScene", [](json& s) { s["camera"]["far"] = 1e12; }, "camera.far", "beyond"},
      {"PositionFarAway", [](json& s) { s["camera"]["position"] = json::array({1e19, 1, 0}); }, "camera.position",
       "farther"},
      {"TargetFarAway", [](json& s) { s["camera"]["target"] = json::array({0, -1e300, 0}); }, "camera.target",
       "farther"},
      {"VertexBeyondTheLimit", [](json& s) { s["objects"][0]["vertices"][1] = json::array({-3, 0, 1e10}); },
       "objects[0].vertices[1]", "beyond"},
      {"TranslateBeyondTheLimit",
       [](json& s) { s["objects"][1]["transform"]["translate"] = json::array({0, -2e9, 0}); },
       "objects[1].transform.translate", "beyond"},
      {"ScaleBeyondTheLimit", [](json& s) { s["objects"][1]["transform"]["scale"] = json::array({1, 1e7, 1}); },
       "objects[1].transform.scale", "beyond"},
      {"RotationBeyondTheLimit",
       [](json& s) { s["objects"][1]["transform"]["rotate_deg"] = json::array({0, 1e300, 0}); },
       "objects[1].transform.rotate_deg", "beyond"},
      {"LightCornerBeyondTheLimit", [](json& s) { s["lights"][0]["polygon"][0] = json::array({-0.5, 2.99, -1e10}); },
       "lights[0].polygon[0]", "beyond"},
      {"RadianceHuge", [](json& s) { s["lights"][0]["radiance"] = json::array({1e13, 1, 1}); }, "lights[0].radiance",
       "beyond"},
  };
  return all;
}

class MalformedScene : public ::testing::TestWithParam<MalformedCase> {};

TEST_P(MalformedScene, IsRefusedWithKeyPath) {
  const MalformedCase& c = GetParam();
  json scene = baseSceneJson();
  c.mutate(scene);
  try {
    (void)sceneFromJson(scene);
    FAIL() << "accepted a malformed scene";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), c.path) << e.what();
    EXPECT_NE(e.problem().find(c.word), std::string::npos) << "message: " << e.what();
    const std::string expectedWhat = e.path().empty() ? e.problem() : e.path() + ": " + e.problem();
    EXPECT_EQ(std::string(e.what()), expectedWhat);
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, MalformedScene, ::testing::ValuesIn(sceneCases()),
                         [](const ::testing::TestParamInfo<MalformedCase>& info) { return info.param.name; });

TEST(MalformedSceneTable, BaseSceneIsValid) {
  // Every case above must fail because of its mutation, not because of the base.
  const Scene scene = sceneFromJson(baseSceneJson());
  EXPECT_EQ(scene.objects().size(), 3u);
  EXPECT_EQ(scene.faces().size(), 13u);
}

TEST(MalformedSceneTable, NonPlanarMessageGivesTheError) {
  json scene = baseSceneJson();
  scene["objects"][0]["vertices"] = liftedFloor(0.02);
  try {
    (void)sceneFromJson(scene);
    FAIL();
  } catch (const ValidationError& e) {
    // The number printed is planarityError() of the face, computed independently here.
    Polygon3 face;
    for (const auto& v : liftedFloor(0.02)) face.push_back(Vec3(v[0].get<double>(), v[1].get<double>(), v[2].get<double>()));
    char expected[64];
    std::snprintf(expected, sizeof expected, "off by %.1e of its size", planarityError(face));
    EXPECT_NE(e.problem().find(expected), std::string::npos) << e.what();
  }
}

TEST(MalformedSceneTable, SlightNonPlanarityWithinToleranceIsAccepted) {
  json scene = baseSceneJson();
  // Planarity error well below kRelativePlanarity of the floor's size.
  scene["objects"][0]["vertices"] = liftedFloor(1e-9);
  EXPECT_NO_THROW((void)sceneFromJson(scene));
}

TEST(MalformedSceneTable, FirstProblemInDocumentOrderIsReported) {
  json scene = baseSceneJson();
  scene["camera"]["near"] = -1;
  scene["objects"][2]["faces"][0][0] = 99;
  scene["objects"][1]["material"] = "gold";
  try {
    (void)sceneFromJson(scene);
    FAIL();
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), "objects[1].material");
  }
}

TEST(MalformedSceneTable, UnknownKeysAreIgnored) {
  json scene = baseSceneJson();
  scene["comment"] = "made by hand";
  scene["objects"][1]["color"] = "#ff0000";
  scene["lights"][0]["note"] = json::array({1, 2});
  scene["camera"]["aperture"] = 2.8;
  EXPECT_NO_THROW((void)sceneFromJson(scene));
}

TEST(MalformedSceneTable, OrthographicCameraIsAccepted) {
  json scene = baseSceneJson();
  scene["camera"]["projection"] = "orthographic";
  scene["camera"]["height"] = 4;
  const Scene parsed = sceneFromJson(scene);
  ASSERT_TRUE(parsed.camera());
  EXPECT_EQ(parsed.camera()->projection, Camera::Projection::Orthographic);
  EXPECT_EQ(parsed.camera()->height, 4);
}

}  // namespace
}  // namespace penumbra::protocol
