// add_light and remove_light over HTTP: an added light changes the mesh and is a counted full
// rebuild, removing it gives back the mesh the scene had, bad ones are refused with 422 and the
// key path (version unchanged), and the journal replays them after a restart.
#include <gtest/gtest.h>

#include <map>

#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {

// A light like Cornell's ceiling light, `scale` of its size, centred at (cx, y, cz).
json lampPolygon(double cx, double y, double cz, double scale) {
  const double hx = 0.65 * scale, hz = 0.525 * scale;
  return {
      {cx - hx, y, cz - hz}, {cx + hx, y, cz - hz}, {cx + hx, y, cz + hz}, {cx - hx, y, cz + hz}};
}

json addLightFrame(const std::string& id, const json& polygon, const json& radiance) {
  return {{"edits",
           {{{"op", "add_light"},
             {"light", {{"id", id}, {"polygon", polygon}, {"radiance", radiance}}}}}}};
}

json removeLightFrame(const std::string& id) {
  return {{"edits", {{{"op", "remove_light"}, {"id", id}}}}};
}

TEST(LightCountEdits, AddedLightChangesTheMeshAndRemovingItRestoresIt) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json before = bodyJson(client.Get((base + "/mesh").c_str()));

  const auto added = postJson(client, base + "/edits",
                          addLightFrame("lamp2", lampPolygon(1.5, 5.0, 1.5, 0.5), {8, 8, 8}));
  ASSERT_EQ(added->status, 200) << added->body;
  const json result = bodyJson(added);
  EXPECT_EQ(result["version"], 1);
  EXPECT_EQ(result["full_rebuild"], true);
  EXPECT_GT(result["tree_rebuilds"].get<int>(), 0);
  const json scene = bodyJson(client.Get(base.c_str()))["scene"];
  ASSERT_EQ(scene["lights"].size(), 2u);
  EXPECT_EQ(scene["lights"][1]["id"], "lamp2");
  EXPECT_EQ(scene["lights"][1]["polygon"], lampPolygon(1.5, 5.0, 1.5, 0.5));
  const json lit = bodyJson(client.Get((base + "/mesh").c_str()));
  EXPECT_FALSE(receiversByKey(lit) == receiversByKey(before));
  EXPECT_FALSE(bodyJson(client.Get((base + "/mesh?since=0").c_str()))["receivers"].empty());

  const auto removed = postJson(client, base + "/edits", removeLightFrame("lamp2"));
  ASSERT_EQ(removed->status, 200) << removed->body;
  EXPECT_EQ(bodyJson(removed)["version"], 2);
  EXPECT_EQ(bodyJson(removed)["full_rebuild"], true);
  EXPECT_TRUE(receiversByKey(bodyJson(client.Get((base + "/mesh").c_str()))) ==
              receiversByKey(before));
}

TEST(LightCountEdits, BadAddAndRemoveAre422WithThePathAndChangeNothing) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json original = bodyJson(client.Get(base.c_str()))["scene"]["lights"];
  const json lamp = lampPolygon(1.5, 5.0, 1.5, 0.5);
  json bent = lamp;
  bent[2][1] = 4.0;
  json noLight = addLightFrame("x", lamp, {1, 1, 1});
  noLight["edits"][0].erase("light");
  json lightNotObject = noLight;
  lightNotObject["edits"][0]["light"] = "lamp";
  const std::vector<std::pair<json, std::string>> cases = {
      {removeLightFrame("ceiling_light"), "edits[0].id"},  // the last light
      {removeLightFrame("sun"), "edits[0].id"},
      {json{{"edits", {{{"op", "remove_light"}, {"id", 4}}}}}, "edits[0].id"},
      {addLightFrame("ceiling_light", lamp, {1, 1, 1}), "edits[0].light.id"},
      {addLightFrame("lamp2", bent, {1, 1, 1}), "edits[0].light.polygon"},
      {addLightFrame("lamp2", lampPolygon(1.5, 45.0, 1.5, 0.5), {1, 1, 1}),
       "edits[0].light.polygon[0]"},
      {addLightFrame("lamp2", lamp, {1, -1, 1}), "edits[0].light.radiance"},
      {noLight, "edits[0].light"},
      {lightNotObject, "edits[0].light"},
  };
  expectLightFramesRefused(client, base, cases, original);
}

TEST(LightCountEdits, JournalReplaysAddAndRemoveLightAfterARestart) {
  const TempDataDir data;
  const ServerOptions options = data.durable();
  std::string id, mesh;
  json lights;
  {
    RunningServer first(options);
    id = first.addBundled("cornell");
    auto client = first.client();
    const std::string base = "/api/scenes/" + id;
    const json lamp = lampPolygon(3.5, 5.2, 2.0, 0.6);
    ASSERT_EQ(postJson(client, base + "/edits", addLightFrame("lamp2", lamp, {6, 6, 6}))->status, 200);
    ASSERT_EQ(postJson(client, base + "/edits", moveFrame("short_block", 1.7, 0, 1.6, -10))->status,
              200);
    ASSERT_EQ(postJson(client, base + "/edits", removeLightFrame("ceiling_light"))->status, 200);
    lights = bodyJson(client.Get(base.c_str()))["scene"]["lights"];
    mesh = client.Get((base + "/mesh?format=bin").c_str())->body;
  }
  ASSERT_EQ(lights.size(), 1u);
  EXPECT_EQ(lights[0]["id"], "lamp2");
  RunningServer second(options);
  const std::vector<RestoredScene> restored = second.server().restore();
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, 3u);
  auto client = second.client();
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"]["lights"], lights);
  EXPECT_TRUE(client.Get(("/api/scenes/" + id + "/mesh?format=bin").c_str())->body == mesh);
}

}  // namespace
}  // namespace penumbra::server::test
