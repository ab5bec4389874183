// set_light over HTTP: a grown light gives the mesh a fresh upload of the edited scene has,
// its delta merges into the old mesh to the new one, bad light edits are refused with 422
// and the key path (version unchanged), the journal replays light edits after a restart, and a
// light frame failing inside the engine or the meshing leaves no trace (atomic frames).
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <new>

#include "scenegen/cubes_scene.h"
#include "server/mesh_binary.h"
#include "server/scene_session.h"
#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {

// Cornell's ceiling light scaled about its centre by `scale` and lowered by `drop`.
json grownLight(double scale, double drop) {
  const double cx = 2.78, cz = 2.795, hx = 0.65 * scale, hz = 0.525 * scale, y = 5.48 - drop;
  return {
      {cx - hx, y, cz - hz}, {cx + hx, y, cz - hz}, {cx + hx, y, cz + hz}, {cx - hx, y, cz + hz}};
}

json lightFrame(const json& fields) {
  json edit = {{"op", "set_light"}, {"id", "ceiling_light"}};
  edit.update(fields);
  return {{"edits", {edit}}};
}

TEST(LightEdits, GrownLightMeshesAsAFreshUploadAndDeltasMerge) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json before = bodyJson(client.Get((base + "/mesh").c_str()));

  const auto edited =
      postJson(client, base + "/edits", lightFrame({{"polygon", grownLight(1.5, 0.1)}}));
  ASSERT_EQ(edited->status, 200) << edited->body;
  EXPECT_EQ(bodyJson(edited)["version"], 1);
  const json scene = bodyJson(client.Get(base.c_str()));
  EXPECT_EQ(scene["version"], 1);
  EXPECT_EQ(scene["scene"]["lights"][0]["polygon"], grownLight(1.5, 0.1));
  EXPECT_EQ(scene["scene"]["lights"][0]["radiance"], json({17.0, 12.0, 4.0}));

  // The old mesh with the delta applied is the new mesh; the new mesh is what a fresh
  // upload of the edited scene serves (the light stays in the room: same bounds).
  const json whole = bodyJson(client.Get((base + "/mesh").c_str()));
  auto merged = receiversByKey(before);
  const json delta = bodyJson(client.Get((base + "/mesh?since=0").c_str()));
  EXPECT_FALSE(delta["receivers"].empty());
  for (const json& r : delta["receivers"]) {
    json copy = r;
    copy.erase("scene_version");
    merged[{r["object"].get<std::string>(), r["face"].get<uint32_t>()}] = copy;
  }
  for (const json& gone : delta["removed"])
    merged.erase({gone["object"].get<std::string>(), gone["face"].get<uint32_t>()});
  EXPECT_TRUE(merged == receiversByKey(whole));
  const auto fresh = postJson(client, "/api/scenes?name=fresh", scene["scene"]);
  ASSERT_EQ(fresh->status, 201) << fresh->body;
  const json freshMesh = bodyJson(
      client.Get(("/api/scenes/" + bodyJson(fresh)["id"].get<std::string>() + "/mesh").c_str()));
  EXPECT_TRUE(receiversByKey(freshMesh) == receiversByKey(whole));

  // Power alone: every lit receiver changes, the version moves on.
  const auto brighter = postJson(client, base + "/edits", lightFrame({{"radiance", {34, 24, 8}}}));
  ASSERT_EQ(brighter->status, 200) << brighter->body;
  EXPECT_EQ(bodyJson(brighter)["version"], 2);
  EXPECT_FALSE(bodyJson(client.Get((base + "/mesh?since=1").c_str()))["receivers"].empty());
}

TEST(LightEdits, BadLightEditsAre422WithThePathAndChangeNothing) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id;
  const json original = bodyJson(client.Get(base.c_str()))["scene"]["lights"];
  json bent = grownLight(1, 0);
  bent[2][1] = 5.0;
  json concave = grownLight(1, 0);
  concave[1] = {2.7, 5.48, 2.75};
  const std::vector<std::pair<json, std::string>> cases = {
      {lightFrame({{"radiance", {1, -2, 3}}}), "edits[0].radiance"},
      {lightFrame({{"polygon", bent}}), "edits[0].polygon"},
      {lightFrame({{"polygon", concave}}), "edits[0].polygon"},
      {lightFrame({{"polygon", grownLight(1, -40)}}), "edits[0].polygon[0]"},  // far above the box
      {lightFrame({{"id", "sun"}, {"radiance", {1, 1, 1}}}), "edits[0].id"},
      {lightFrame(json::object()), "edits[0]"},
  };
  expectLightFramesRefused(client, base, cases, original);
}

TEST(LightEdits, JournalReplaysLightEditsAfterARestart) {
  const TempDataDir data;
  const ServerOptions options = data.durable();
  std::string id, mesh;
  {
    RunningServer first(options);
    id = first.addBundled("cornell");
    auto client = first.client();
    const std::string base = "/api/scenes/" + id;
    ASSERT_EQ(
        postJson(client, base + "/edits", lightFrame({{"polygon", grownLight(0.6, 0.2)}}))->status,
        200);
    ASSERT_EQ(postJson(client, base + "/edits", moveFrame("short_block", 1.7, 0, 1.6, -10))->status,
              200);
    ASSERT_EQ(postJson(client, base + "/edits", lightFrame({{"radiance", {5, 5, 5}}}))->status, 200);
    mesh = client.Get((base + "/mesh?format=bin").c_str())->body;
  }
  RunningServer second(options);
  const std::vector<RestoredScene> restored = second.server().restore();
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_TRUE(restored[0].problem.empty()) << restored[0].problem;
  EXPECT_EQ(restored[0].version, 3u);
  auto client = second.client();
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()));
  EXPECT_EQ(scene["scene"]["lights"][0]["polygon"], grownLight(0.6, 0.2));
  EXPECT_EQ(scene["scene"]["lights"][0]["radiance"], json({5.0, 5.0, 5.0}));
  EXPECT_TRUE(client.Get(("/api/scenes/" + id + "/mesh?format=bin").c_str())->body == mesh);
}

// Light frames failing at each point they pass (the rebuild of a moved, added or removed light,
// the incremental path of a radiance-only one, the meshing), as out of memory or an internal error: nothing is
// published, and the session then goes on exactly as one that never saw the failure.
TEST(LightEdits, FailedLightFramesLeaveNoTrace) {
  struct Injector {
    std::string target;
    bool armed = false, outOfMemory = false, fired = false;
  };
  auto injector = std::make_shared<Injector>();
  EngineSettings hooked;
  hooked.failurePoint = [injector](const char* point) {
    if (!injector->armed) return;
    // An internal error mid-frame is met by the engine's fallback rebuild: make it fail too.
    if (injector->fired && !injector->outOfMemory && std::string(point) == "rebuild")
      throw std::logic_error("fallback fails too");
    if (injector->fired || injector->target != point) return;
    injector->fired = true;
    if (injector->outOfMemory) throw std::bad_alloc();
    throw std::logic_error(std::string("injected at ") + point);
  };
  const Scene scene = makeCubesScene(CubesSceneOptions{6, 5});
  SceneSession tested("s", "cubes", scene, hooked);
  SceneSession reference("s", "cubes", scene);
  const Light light = scene.lights()[0];
  auto setLight = [](const std::string& id, std::optional<Polygon3> polygon,
                     std::optional<Vec3> radiance) {
    Edit edit;
    edit.op = Edit::Op::SetLight;
    edit.id = id;
    edit.polygon = std::move(polygon);
    edit.radiance = radiance;
    return Frame{{edit}};
  };
  Polygon3 moved = light.polygon;
  for (Vec3& p : moved) p += Vec3(0.3, -0.1, 0.2);
  Frame added{{Edit{}}}, removed{{Edit{}}};
  added.edits[0].op = Edit::Op::AddLight;
  added.edits[0].id = "lamp2";
  added.edits[0].light = Light{"lamp2", moved, Vec3(2.0)};
  removed.edits[0].op = Edit::Op::RemoveLight;
  removed.edits[0].id = "lamp2";
  const std::vector<std::pair<Frame, std::vector<std::string>>> frames = {
      {setLight("light", moved, std::nullopt), {"rebuild", "meshing"}},
      {setLight("light", std::nullopt, Vec3(3, 4, 5)), {"removed", "added", "meshing"}},
      {setLight("light", light.polygon, light.radiance), {"rebuild", "meshing"}},
      {added, {"rebuild", "meshing"}},
      {removed, {"rebuild", "meshing"}},
  };
  auto bytes = [](const SceneSnapshot& s) {
    return mesh_binary::encode(s, s.select(std::nullopt));
  };
  for (size_t f = 0; f < frames.size(); ++f) {
    for (const std::string& point : frames[f].second)
      for (bool outOfMemory : {false, true}) {
        const std::string when =
            "frame " + std::to_string(f) + " at " + point + (outOfMemory ? " (no memory)" : "");
        const auto before = tested.snapshot();
        *injector = Injector{point, true, outOfMemory, false};
        EXPECT_ANY_THROW(tested.apply(frames[f].first)) << when;
        injector->armed = false;
        EXPECT_TRUE(injector->fired) << when;
        EXPECT_EQ(tested.snapshot(), before) << when;
      }
    const auto a = tested.apply(frames[f].first);
    const auto b = reference.apply(frames[f].first);
    EXPECT_EQ(a.snapshot->version, b.snapshot->version);
    EXPECT_EQ(protocol::sceneToJson(a.snapshot->scene), protocol::sceneToJson(b.snapshot->scene));
    EXPECT_TRUE(bytes(*a.snapshot) == bytes(*b.snapshot)) << "frame " << f << ": mesh";
  }
}

}  // namespace
}  // namespace penumbra::server::test
