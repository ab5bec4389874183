// Edit frames and .edits.jsonl scripts: every refusal names the exact key path
// (and, in scripts, the line); valid frames round-trip exactly.
#include "protocol/edits_json.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "protocol/frame_result_json.h"
#include "protocol/scene_json.h"
#include "scene_fixtures.h"

namespace penumbra::protocol {
namespace {

using nlohmann::json;

// A valid frame: move box1, remove box2, add box9 (red).
json baseFrame() {
  json cube = {{"id", "box9"},
               {"vertices", testing::cubeVertices()},
               {"faces", testing::cubeFaces()},
               {"material", "red"},
               {"transform", {{"translate", {-1.5, 0.5, 0}}}}};
  return {{"edits",
           {{{"op", "move"},
             {"id", "box1"},
             {"transform", {{"translate", {0.1, 0.5, 0}}, {"rotate_deg", {0, 35, 0}}}}},
            {{"op", "remove"}, {"id", "box2"}},
            {{"op", "add"}, {"object", cube}}}}};
}

// A set_light edit: a 1 m square light facing down at y = 2.9, and a radiance.
json lightEdit() {
  return {{"op", "set_light"},
          {"id", "lamp"},
          {"polygon", {{-0.5, 2.9, -0.5}, {0.5, 2.9, -0.5}, {0.5, 2.9, 0.5}, {-0.5, 2.9, 0.5}}},
          {"radiance", {10, 9, 8}}};
}

// Replaces edit 1 (the remove) by lightEdit() changed by `mutate`.
std::function<void(json&)> withLight(std::function<void(json&)> mutate) {
  return [mutate](json& f) {
    f["edits"][1] = lightEdit();
    mutate(f["edits"][1]);
  };
}

// An add_light edit: a new 1 m square light "lamp2" facing down at y = 2.9.
json addLightEdit() {
  json light = lightEdit();
  light.erase("op");
  light["id"] = "lamp2";
  return {{"op", "add_light"}, {"light", light}};
}

// Replaces edit 1 (the remove) by `edit` changed by `mutate`.
std::function<void(json&)> withEdit(json edit, std::function<void(json&)> mutate) {
  return [edit, mutate](json& f) {
    f["edits"][1] = edit;
    mutate(f["edits"][1]);
  };
}

std::vector<Material> materials() {
  return {Material{"red", Vec3(0.7, 0.1, 0.1)}, Material{"white", Vec3(0.8)}};
}

struct MalformedFrame {
  const char* name;
  std::function<void(json&)> mutate;
  const char* path;
  const char* word;  // must appear in problem()
};

const std::vector<MalformedFrame>& frameCases() {
  static const std::vector<MalformedFrame> all = {
      {"RootNotObject", [](json& f) { f = json::array(); }, "", "expected an object"},
      {"MissingEdits", [](json& f) { f.erase("edits"); }, "edits", "missing required key"},
      {"EditsNotArray", [](json& f) { f["edits"] = json::object(); }, "edits", "expected an array"},
      {"EditNotObject", [](json& f) { f["edits"][1] = 3; }, "edits[1]", "expected an object"},
      {"MissingOp", [](json& f) { f["edits"][0].erase("op"); }, "edits[0].op",
       "missing required key"},
      {"OpNotString", [](json& f) { f["edits"][0]["op"] = 1; }, "edits[0].op", "expected a string"},
      {"UnknownOp", [](json& f) { f["edits"][1]["op"] = "rotate"; }, "edits[1].op",
       "unknown op 'rotate'"},
      {"MoveMissingId", [](json& f) { f["edits"][0].erase("id"); }, "edits[0].id",
       "missing required key"},
      {"MoveEmptyId", [](json& f) { f["edits"][0]["id"] = ""; }, "edits[0].id", "empty"},
      {"MoveIdNotString", [](json& f) { f["edits"][0]["id"] = 7; }, "edits[0].id",
       "expected a string"},
      {"MoveMissingTransform", [](json& f) { f["edits"][0].erase("transform"); },
       "edits[0].transform", "missing required key"},
      {"MoveTransformNotObject", [](json& f) { f["edits"][0]["transform"] = json::array(); },
       "edits[0].transform", "expected an object"},
      {"MoveZeroScale",
       [](json& f) {
         f["edits"][0]["transform"]["scale"] = {1, 0, 1};
       },
       "edits[0].transform.scale", "zero"},
      {"MoveShortTranslate",
       [](json& f) {
         f["edits"][0]["transform"]["translate"] = {1, 2};
       },
       "edits[0].transform.translate", "3"},
      {"MoveNonFiniteRotation",
       [](json& f) {
         f["edits"][0]["transform"]["rotate_deg"] = {0, std::numeric_limits<double>::infinity(), 0};
       },
       "edits[0].transform.rotate_deg[1]", "finite"},
      {"MoveNaNTranslate",
       [](json& f) {
         f["edits"][0]["transform"]["translate"][2] = std::numeric_limits<double>::quiet_NaN();
       },
       "edits[0].transform.translate[2]", "finite"},
      {"MoveScaleNotArray", [](json& f) { f["edits"][0]["transform"]["scale"] = 2; },
       "edits[0].transform.scale", "3 numbers"},
      {"RemoveMissingId", [](json& f) { f["edits"][1].erase("id"); }, "edits[1].id",
       "missing required key"},
      {"RemoveIdNull", [](json& f) { f["edits"][1]["id"] = nullptr; }, "edits[1].id",
       "expected a string"},
      {"AddMissingObject", [](json& f) { f["edits"][2].erase("object"); }, "edits[2].object",
       "missing required key"},
      {"AddObjectMissingId", [](json& f) { f["edits"][2]["object"].erase("id"); },
       "edits[2].object.id", "missing required key"},
      {"AddObjectMissingFaces", [](json& f) { f["edits"][2]["object"].erase("faces"); },
       "edits[2].object.faces", "missing required key"},
      {"AddFaceIndexOutOfRange", [](json& f) { f["edits"][2]["object"]["faces"][3][1] = 8; },
       "edits[2].object.faces[3][1]", "8"},
      {"AddFaceNotPlanar",
       [](json& f) {
         f["edits"][2]["object"]["vertices"][6] = {0.5, 0.9, 0.5};
       },
       "edits[2].object.faces[5]", "planar"},
      {"AddZeroScale",
       [](json& f) {
         f["edits"][2]["object"]["transform"]["scale"] = {0, 1, 1};
       },
       "edits[2].object.transform.scale", "zero"},
      {"AddUnknownMaterial", [](json& f) { f["edits"][2]["object"]["material"] = "gold"; },
       "edits[2].object.material", "unknown material 'gold'"},
      {"AddVertexNotArray", [](json& f) { f["edits"][2]["object"]["vertices"][0] = "x"; },
       "edits[2].object.vertices[0]", "3 numbers"},
      {"SetLightMissingId", withLight([](json& e) { e.erase("id"); }), "edits[1].id", "missing required key"},
      {"SetLightNeither", withLight([](json& e) { e.erase("polygon"), e.erase("radiance"); }), "edits[1]",
       "changes nothing"},
      {"SetLightPolygonNotArray", withLight([](json& e) { e["polygon"] = 1; }), "edits[1].polygon",
       "expected an array"},
      {"SetLightPolygonTwoPoints", withLight([](json& e) { e["polygon"].erase(2), e["polygon"].erase(2); }),
       "edits[1].polygon", "at least 3"},
      {"SetLightVertexNotArray", withLight([](json& e) { e["polygon"][2] = "x"; }), "edits[1].polygon[2]",
       "3 numbers"},
      {"SetLightPolygonNotPlanar", withLight([](json& e) { e["polygon"][2][1] = 2.5; }), "edits[1].polygon",
       "planar"},
      {"SetLightPolygonNotConvex", withLight([](json& e) { e["polygon"][2] = {-0.1, 2.9, -0.1}; }),
       "edits[1].polygon", "convex"},
      {"SetLightRadianceNegative", withLight([](json& e) { e["radiance"][0] = -1; }), "edits[1].radiance",
       "negative"},
      {"SetLightRadianceNaN",
       withLight([](json& e) { e["radiance"][1] = std::numeric_limits<double>::quiet_NaN(); }),
       "edits[1].radiance[1]", "finite"},
      {"AddLightMissingLight", withEdit(addLightEdit(), [](json& e) { e.erase("light"); }), "edits[1].light",
       "missing required key"},
      {"AddLightNotObject", withEdit(addLightEdit(), [](json& e) { e["light"] = {1, 2}; }), "edits[1].light",
       "object"},
      {"AddLightMissingId", withEdit(addLightEdit(), [](json& e) { e["light"].erase("id"); }),
       "edits[1].light.id", "missing required key"},
      {"AddLightIdNumber", withEdit(addLightEdit(), [](json& e) { e["light"]["id"] = 7; }), "edits[1].light.id",
       "expected a string"},
      {"AddLightMissingPolygon", withEdit(addLightEdit(), [](json& e) { e["light"].erase("polygon"); }),
       "edits[1].light.polygon", "missing required key"},
      {"AddLightVertexNaN",
       withEdit(addLightEdit(), [](json& e) { e["light"]["polygon"][1][2] = std::numeric_limits<double>::quiet_NaN(); }),
       "edits[1].light.polygon[1][2]", "finite"},
      {"AddLightPolygonNotConvex",
       withEdit(addLightEdit(), [](json& e) { e["light"]["polygon"][2] = {-0.1, 2.9, -0.1}; }),
       "edits[1].light.polygon", "convex"},
      {"AddLightMissingRadiance", withEdit(addLightEdit(), [](json& e) { e["light"].erase("radiance"); }),
       "edits[1].light.radiance", "missing required key"},
      {"AddLightRadianceNegative", withEdit(addLightEdit(), [](json& e) { e["light"]["radiance"][2] = -1; }),
       "edits[1].light.radiance", "negative"},
      {"RemoveLightMissingId", withEdit({{"op", "remove_light"}}, [](json&) {}), "edits[1].id",
       "missing required key"},
      {"RemoveLightIdNumber", withEdit({{"op", "remove_light"}, {"id", 3}}, [](json&) {}), "edits[1].id",
       "expected a string"},
      {"UnknownLightOp", withEdit({{"op", "delete_light"}, {"id", "lamp"}}, [](json&) {}), "edits[1].op",
       "remove_light"},
  };
  return all;
}

class MalformedFrameTest : public ::testing::TestWithParam<size_t> {};

TEST_P(MalformedFrameTest, RefusedWithExactKeyPath) {
  const MalformedFrame& c = frameCases()[GetParam()];
  json frame = baseFrame();
  c.mutate(frame);
  const auto known = materials();
  try {
    frameFromJson(frame, &known);
    FAIL() << c.name << ": accepted";
  } catch (const ValidationError& error) {
    EXPECT_EQ(error.path(), c.path) << c.name << ": " << error.what();
    EXPECT_NE(error.problem().find(c.word), std::string::npos) << c.name << ": " << error.what();
  }
}

INSTANTIATE_TEST_SUITE_P(Cases, MalformedFrameTest, ::testing::Range<size_t>(0, frameCases().size()),
                         [](const auto& info) { return std::string(frameCases()[info.param].name); });

TEST(EditsJson, ReadsEveryOpWithDefaults) {
  const auto known = materials();
  const Frame frame = frameFromJson(baseFrame(), &known);
  ASSERT_EQ(frame.edits.size(), 3u);
  EXPECT_EQ(frame.edits[0].op, Edit::Op::Move);
  EXPECT_EQ(frame.edits[0].id, "box1");
  EXPECT_EQ(frame.edits[0].transform.translate, Vec3(0.1, 0.5, 0));
  EXPECT_EQ(frame.edits[0].transform.rotateDeg, Vec3(0, 35, 0));
  EXPECT_EQ(frame.edits[0].transform.scale, Vec3(1.0));  // omitted: default
  EXPECT_EQ(frame.edits[1].op, Edit::Op::Remove);
  EXPECT_EQ(frame.edits[1].id, "box2");
  EXPECT_EQ(frame.edits[2].op, Edit::Op::Add);
  EXPECT_EQ(frame.edits[2].id, "box9");
  EXPECT_EQ(frame.edits[2].object.id, "box9");
  EXPECT_EQ(frame.edits[2].object.material, "red");
  EXPECT_EQ(frame.edits[2].object.faces.size(), 6u);
  EXPECT_EQ(frame.edits[2].object.transform.translate, Vec3(-1.5, 0.5, 0));
}

TEST(EditsJson, WithoutMaterialListAnyNameIsLeftToTheEngine) {
  json frame = baseFrame();
  frame["edits"][2]["object"]["material"] = "gold";
  EXPECT_EQ(frameFromJson(frame).edits[2].object.material, "gold");
  frame["edits"][2]["object"]["faces"][0][0] = 9;  // other object checks still run
  EXPECT_THROW(frameFromJson(frame), ValidationError);
}

TEST(EditsJson, EmptyFrameAndUnknownKeysAreAccepted) {
  EXPECT_TRUE(frameFromJson(json{{"edits", json::array()}}).edits.empty());
  json frame = baseFrame();
  frame["comment"] = "ignored";
  frame["edits"][1]["why"] = "ignored too";
  EXPECT_EQ(frameFromJson(frame).edits.size(), 3u);
}

TEST(EditsJson, RoundTripIsExact) {
  const auto known = materials();
  json source = baseFrame();
  source["edits"][0]["transform"]["translate"] = {0.1 + 1e-16, 1.0 / 3.0, -2.0 / 7.0};
  source["edits"][0]["transform"]["scale"] = {-1, 2.5, 1e-3};
  const Frame frame = frameFromJson(source, &known);
  const json written = frameToJson(frame);
  const Frame again = frameFromJson(written, &known);
  EXPECT_EQ(frameToJson(again), written);
  EXPECT_EQ(again.edits[0].transform, frame.edits[0].transform);
  EXPECT_EQ(again.edits[2].object.vertices, frame.edits[2].object.vertices);
  EXPECT_EQ(again.edits[2].object.faces, frame.edits[2].object.faces);

  // Through the script text too.
  const std::vector<Frame> frames{frame, Frame{}, again};
  const std::string text = writeEditScript(frames);
  const std::vector<Frame> read = readEditScript(text, &known);
  ASSERT_EQ(read.size(), 3u);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(frameToJson(read[i]), frameToJson(frames[i]));
}

TEST(EditsJson, SetLightReadsEitherOrBothAndRoundTrips) {
  json source = {{"edits", {lightEdit()}}};
  source["edits"][0]["polygon"][0] = {-0.5 + 1e-16, 2.9, -1.0 / 3.0};
  const Frame frame = frameFromJson(source);
  ASSERT_EQ(frame.edits.size(), 1u);
  EXPECT_EQ(frame.edits[0].op, Edit::Op::SetLight);
  EXPECT_EQ(frame.edits[0].id, "lamp");
  ASSERT_TRUE(frame.edits[0].polygon && frame.edits[0].radiance);
  EXPECT_EQ(frame.edits[0].polygon->size(), 4u);
  EXPECT_EQ(*frame.edits[0].radiance, Vec3(10, 9, 8));
  const Frame again = frameFromJson(frameToJson(frame));
  EXPECT_EQ(again.edits[0].polygon, frame.edits[0].polygon);
  EXPECT_EQ(frameToJson(again), frameToJson(frame));

  json radianceOnly = lightEdit();
  radianceOnly.erase("polygon");
  const Frame power = frameFromJson(json{{"edits", {radianceOnly}}});
  EXPECT_FALSE(power.edits[0].polygon);
  EXPECT_FALSE(frameToJson(power)["edits"][0].contains("polygon"));
  json polygonOnly = lightEdit();
  polygonOnly.erase("radiance");
  const Frame place = frameFromJson(json{{"edits", {polygonOnly}}});
  EXPECT_FALSE(place.edits[0].radiance);
  EXPECT_FALSE(frameToJson(place)["edits"][0].contains("radiance"));
}

TEST(EditsJson, AddAndRemoveLightRoundTrip) {
  json source = {{"edits", {addLightEdit(), {{"op", "remove_light"}, {"id", "lamp"}}}}};
  source["edits"][0]["light"]["polygon"][0] = {-0.5 + 1e-16, 2.9, -1.0 / 3.0};
  const Frame frame = frameFromJson(source);
  ASSERT_EQ(frame.edits.size(), 2u);
  EXPECT_EQ(frame.edits[0].op, Edit::Op::AddLight);
  EXPECT_EQ(frame.edits[0].id, "lamp2");
  EXPECT_EQ(frame.edits[0].light.id, "lamp2");
  EXPECT_EQ(frame.edits[0].light.polygon.size(), 4u);
  EXPECT_EQ(frame.edits[0].light.polygon[0].z, -1.0 / 3.0);
  EXPECT_EQ(frame.edits[0].light.radiance, Vec3(10, 9, 8));
  EXPECT_EQ(frame.edits[1].op, Edit::Op::RemoveLight);
  EXPECT_EQ(frame.edits[1].id, "lamp");
  const json written = frameToJson(frame);
  EXPECT_EQ(written["edits"][0]["op"], "add_light");
  EXPECT_EQ(written["edits"][1], (json{{"op", "remove_light"}, {"id", "lamp"}}));
  const Frame again = frameFromJson(written);
  EXPECT_EQ(again.edits[0].light.polygon, frame.edits[0].light.polygon);
  EXPECT_EQ(frameToJson(again), written);
  const std::vector<Frame> read = readEditScript(writeEditScript({frame}));
  ASSERT_EQ(read.size(), 1u);
  EXPECT_EQ(frameToJson(read[0]), written);
}

TEST(EditScript, LinesAreCountedWithBlankLines) {
  const std::string frame = baseFrame().dump();
  const std::string text = frame + "\n\n   \n" + frame + "\r\n" + frame;  // no final newline
  const auto frames = readEditScriptFrames(text);
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames[0].line, 1u);
  EXPECT_EQ(frames[1].line, 4u);
  EXPECT_EQ(frames[2].line, 5u);
  EXPECT_TRUE(readEditScript("").empty());
  EXPECT_TRUE(readEditScript("\n\n").empty());
}

// The error of a script whose line `bad` (1-based, blank lines in between) holds
// the given text.
EditScriptError scriptError(const std::string& badLine, size_t& badLineNumber) {
  const std::string good = baseFrame().dump();
  const std::string text =
      good + "\n\n" + good + "\n" + good + "\n\n\n" + badLine + "\n" + good + "\n";
  badLineNumber = 7;
  try {
    readEditScript(text);
  } catch (const EditScriptError& error) {
    return error;
  }
  ADD_FAILURE() << "accepted: " << badLine;
  return EditScriptError(0, "", "");
}

TEST(EditScript, ErrorsNameTheLineAndKeyPath) {
  size_t line = 0;
  json frame = baseFrame();
  frame["edits"][0].erase("id");
  EditScriptError error = scriptError(frame.dump(), line);
  EXPECT_EQ(error.line(), line);
  EXPECT_EQ(error.path(), "edits[0].id");
  EXPECT_EQ(std::string(error.what()), "line 7: edits[0].id: missing required key 'id'");

  frame = baseFrame();
  frame["edits"][1]["op"] = "teleport";
  error = scriptError(frame.dump(), line);
  EXPECT_EQ(error.line(), 7u);
  EXPECT_EQ(error.path(), "edits[1].op");

  error = scriptError("{\"edits\": [", line);
  EXPECT_EQ(error.line(), 7u);
  EXPECT_EQ(error.path(), kJsonTextPath);
  EXPECT_EQ(std::string(error.what()).rfind("line 7: (json): ", 0), 0u) << error.what();

  error = scriptError(
      "{\"edits\": [{\"op\": \"move\", \"id\": \"a\", \"transform\": {\"scale\": [1, 1e999, 1]}}]}",
      line);
  EXPECT_EQ(error.line(), 7u);
}

TEST(EditScript, EngineErrorsGetTheLine) {
  const EditScriptError error = atLine(3, EditError(0, "id", "unknown object 'ghost'"));
  EXPECT_EQ(error.line(), 3u);
  EXPECT_EQ(error.path(), "edits[0].id");
  EXPECT_EQ(error.problem(), "unknown object 'ghost'");
  EXPECT_EQ(std::string(error.what()), "line 3: edits[0].id: unknown object 'ghost'");
  EXPECT_EQ(std::string(atLine(9, EditError(2, "", "bad")).what()), "line 9: edits[2]: bad");
}

TEST(FrameResultJson, NamesReceiversByObjectId) {
  const Scene scene = sceneFromJson(testing::baseSceneJson());
  FrameResult result;
  result.version = 4;
  result.seconds = {0.5, 0.25, 0.125};
  result.verticesRelit = 10;
  result.verticesChanged = 7;
  result.verticesCreated = 3;
  result.changedReceivers = {FaceId{0, 0}, FaceId{2, 5}};
  result.removedReceivers = {FaceId{1, 1}, FaceId{42, 0}};
  result.treeRebuilds = 2;
  const json out = frameResultToJson(result, scene);
  EXPECT_EQ(out["version"], 4);
  EXPECT_EQ(out["seconds"]["total"], 0.875);
  EXPECT_EQ(out["vertices"]["relit"], 10);
  EXPECT_EQ(out["vertices"]["changed"], 7);
  EXPECT_EQ(out["vertices"]["created"], 3);
  EXPECT_EQ(out["changed_receivers"],
            json::parse(R"([{"object":"floor","face":0},{"object":"box2","face":5}])"));
  EXPECT_EQ(out["removed_receivers"][1], json::parse(R"({"handle":42,"face":0})"));
  EXPECT_EQ(out["changed_receivers_count"], 2);
  EXPECT_EQ(out["tree_rebuilds"], 2);
}

// Each (frame text, key path): the frame is refused naming that path.
void expectRefusedAt(const std::vector<std::pair<std::string, std::string>>& refused) {
  for (const auto& [body, path] : refused) {
    try {
      frameFromJson(json::parse(body));
      ADD_FAILURE() << body << " was read";
    } catch (const ValidationError& error) {
      EXPECT_EQ(error.path(), path) << body << ": " << error.what();
    }
  }
}

TEST(EditsJson, SetMaterialReadsAMaterialAndRoundTrips) {
  const json text = json::parse(
      R"({"edits": [{"op": "set_material", "id": "paint", "material": {"type": "conductor", "roughness": 0.2, "albedo": [0.9, 0.1, 0.1]}}]})");
  const Frame frame = frameFromJson(text);
  ASSERT_EQ(frame.edits.size(), 1u);
  EXPECT_EQ(frame.edits[0].op, Edit::Op::SetMaterial);
  EXPECT_EQ(frame.edits[0].material.id, "paint");
  EXPECT_EQ(frame.edits[0].material.type, MaterialType::Conductor);
  EXPECT_EQ(frameFromJson(frameToJson(frame)).edits[0].material, frame.edits[0].material);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {R"({"edits": [{"op": "set_material", "material": {"albedo": [1, 1, 1]}}]})", "edits[0].id"},
      {R"({"edits": [{"op": "set_material", "id": "p"}]})", "edits[0].material"},
      {R"({"edits": [{"op": "set_material", "id": "p", "material": 3}]})", "edits[0].material"},
      {R"({"edits": [{"op": "set_material", "id": "p", "material": {"albedo": [2, 0, 0]}}]})",
       "edits[0].material.albedo"},
      {R"({"edits": [{"op": "set_material", "id": "p", "material": {"type": "plastic", "albedo": [1, 0, 0]}}]})",
       "edits[0].material.type"},
      {R"({"edits": [{"op": "set_material", "id": "p", "material": {"albedo": [1, 0, 0], "ior": 1.5}}]})",
       "edits[0].material.ior"},
  };
  expectRefusedAt(refused);
  // With the scene's materials, a later add may name the material the frame sets; an earlier one not.
  const std::vector<Material> materials = {Material{"red", Vec3(0.8, 0.1, 0.1)}};
  json frameText = baseFrame();
  frameText["edits"][2]["object"]["material"] = "paint";
  frameText["edits"].insert(
      frameText["edits"].begin(),
      json::parse(R"({"op": "set_material", "id": "paint", "material": {"albedo": [0.2, 0.2, 0.2]}})"));
  EXPECT_NO_THROW(frameFromJson(frameText, &materials));
  std::swap(frameText["edits"][0], frameText["edits"][3]);
  EXPECT_THROW(frameFromJson(frameText, &materials), ValidationError);
}

TEST(EditsJson, VolumeEditsReadTheirKeysAndRoundTrip) {
  const json text =
      json::parse(R"({"edits": [{"op": "set_volume", "id": "smoke", "isovalue": 90.5}]})");
  const Frame frame = frameFromJson(text);
  ASSERT_EQ(frame.edits.size(), 1u);
  EXPECT_EQ(frame.edits[0].op, Edit::Op::SetVolume);
  EXPECT_EQ(frame.edits[0].isovalue, 90.5);
  EXPECT_EQ(frameToJson(frame), text);
  const std::vector<std::pair<std::string, std::string>> refused = {
      {R"({"edits": [{"op": "set_volume", "id": "smoke"}]})", "edits[0].isovalue"},
      {R"({"edits": [{"op": "set_volume", "id": "smoke", "isovalue": "1"}]})", "edits[0].isovalue"},
      {R"({"edits": [{"op": "set_volume", "isovalue": 1}]})", "edits[0].id"},
      {R"({"edits": [{"op": "add_volume"}]})", "edits[0].volume"},
      {R"({"edits": [{"op": "add_volume", "volume": {"id": "v", "file": "x.nrrd", "isovalue": 1}}]})",
       "edits[0].volume.type"},
      // Without files (a frame sent over HTTP) a volume's file is never opened.
      {R"({"edits": [{"op": "add_volume", "volume": {"id": "v", "type": "volume", "file": "/etc/passwd", "isovalue": 1}}]})",
       "edits[0].volume.file"},
  };
  expectRefusedAt(refused);
  // Files the server holds only: a path outside them is refused before it is opened.
  VolumeFiles known;
  known.onlyKnown = true;
  known.knownDirectory = known.baseDirectory = "/tmp/penumbra-uploads";
  for (const char* file :
       {"/etc/passwd", "../passwd", "/tmp/penumbra-uploads/../x.nrrd", "sub/x.nrrd"}) {
    const json body = {
        {"edits",
         {{{"op", "add_volume"},
           {"volume", {{"id", "v"}, {"type", "volume"}, {"file", file}, {"isovalue", 1}}}}}}};
    try {
      frameFromJson(body, nullptr, &known);
      ADD_FAILURE() << file << " was read";
    } catch (const ValidationError& error) {
      EXPECT_EQ(error.path(), "edits[0].volume.file") << file;
      EXPECT_NE(std::string(error.what()).find("not a volume file this server holds"),
                std::string::npos)
          << file << ": " << error.what();
    }
  }
}

}  // namespace
}  // namespace penumbra::protocol
