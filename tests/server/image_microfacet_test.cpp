// GET /image on microfacet scenes: the DM's exact visibility from the snapshot's frozen occluder
// lists (the same image, byte for byte, as rendering with the engine's trees, before and after an
// edit), progressive `samples` with its bounds, hostile values, and images during edits.
#include <gtest/gtest.h>

#include <atomic>
#include <thread>

#include "core/engine/engine.h"
#include "core/render/renderer.h"
#include "imageio/image_encoding.h"
#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

const std::string kView = "&position=0.5,2.2,5&target=0,0.4,0";

// The PNG the CLI's way gives: a fresh engine on `scene` (after `frames`), its mesh, occluder
// lists read from its trees (cli/cli_render.cpp), the route's samples and camera.
std::string expectedPng(const Scene& scene, const std::vector<Frame>& frames, int width, int height,
                        int samples) {
  Engine engine(scene, EngineSettings{});
  for (const Frame& frame : frames)
    engine.compactTrees(engine.apply(frame).changedReceivers);  // as the session
  RenderSettings settings;
  settings.width = width;
  settings.height = height;
  Camera camera = *scene.camera();
  camera.position = Vec3(0.5, 2.2, 5);
  camera.target = Vec3(0, 0.4, 0);
  settings.camera = camera;
  settings.microfacet.pathsPerPixel = samples;
  settings.microfacet.lightSamples = std::clamp(samples, 4, 16);
  settings.occluders = [&engine](FaceId face, const Vec3& p, size_t light,
                                 std::vector<FaceId>& out) {
    const Engine::Receiver* receiver = engine.receiver(face);
    if (!receiver) return;
    for (const OccluderEntry& e :
         receiver->tree.occluders(receiver->tree.locate(receiver->frame.to2D(p))))
      if (e.light == light && e.face != kLightPlaneOccluder) out.push_back(e.face);
  };
  const std::vector<uint8_t> bytes = imageio::encodePng(render(engine.scene(), engine.mesh(), settings));
  return std::string(bytes.begin(), bytes.end());
}

Frame moveGoldBox(const Scene& scene, double x, double z) {
  Edit move;
  move.op = Edit::Op::Move;
  move.id = "gold_box";
  move.transform = scene.objects()[*scene.findObject("gold_box")].transform;
  move.transform.translate = Vec3(x, move.transform.translate.y, z);
  return Frame{{move}};
}

json moveJson(const Scene& scene, double x, double z) {
  const Transform& t = scene.objects()[*scene.findObject("gold_box")].transform;
  const json transform = {{"translate", {x, t.translate.y, z}},
                          {"rotate_deg", {t.rotateDeg.x, t.rotateDeg.y, t.rotateDeg.z}},
                          {"scale", {t.scale.x, t.scale.y, t.scale.z}}};
  return {{"edits", json::array({{{"op", "move"}, {"id", "gold_box"}, {"transform", transform}}})}};
}

TEST(ImageMicrofacet, UsesTheDmOccluderListsBeforeAndAfterAnEdit) {
  RunningServer running;
  const std::string id = running.addBundled("materials");
  const Scene scene = protocol::loadSceneFile(scenePath("materials"));
  auto client = running.client();
  const std::string url = "/api/scenes/" + id + "/image?width=64&height=48&samples=2" + kView;
  const auto before = client.Get(url.c_str());
  ASSERT_EQ(before->status, 200) << before->body;
  EXPECT_EQ(before->get_header_value("X-Penumbra-Samples"), "2");
  EXPECT_TRUE(before->body == expectedPng(scene, {}, 64, 48, 2))
      << "differs from the engine's render";

  const auto edit = postJson(client, "/api/scenes/" + id + "/edits", moveJson(scene, 0.3, 0.6));
  ASSERT_EQ(edit->status, 200) << edit->body;
  const json answer = bodyJson(edit);
  EXPECT_GT(answer["occluder_receivers_count"].get<int>(),
            0);  // the floor's lists were frozen again
  // Freezing them was timed: a frame that froze lists spent time on it.
  EXPECT_GT(answer["occluder_seconds"].get<double>(), 0);
  const auto after = client.Get(url.c_str());
  ASSERT_EQ(after->status, 200) << after->body;
  EXPECT_EQ(after->get_header_value("X-Penumbra-Version"), "1");
  EXPECT_NE(after->body, before->body);
  EXPECT_TRUE(after->body == expectedPng(scene, {moveGoldBox(scene, 0.3, 0.6)}, 64, 48, 2))
      << "differs from the engine's render";
}

TEST(ImageMicrofacet, DiffuseScenesFreezeNothing) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const json scene = bodyJson(client.Get(("/api/scenes/" + id).c_str()))["scene"];
  const std::string object = scene["objects"][scene["objects"].size() - 1]["id"];
  const auto edit = postJson(client, "/api/scenes/" + id + "/edits", moveFrame(object, 3, 0.5, 3));
  ASSERT_EQ(edit->status, 200) << edit->body;
  EXPECT_EQ(bodyJson(edit)["occluder_receivers_count"], 0);
}

TEST(ImageMicrofacet, SamplesRefineAndDefaultWithinTheBudget) {
  RunningServer running;
  const std::string id = running.addBundled("materials");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/image?width=48&height=36" + kView;
  const auto fast = client.Get((base + "&samples=1").c_str());
  const auto fine = client.Get((base + "&samples=8").c_str());
  const auto standard = client.Get(base.c_str());
  ASSERT_EQ(fast->status, 200) << fast->body;
  ASSERT_EQ(fine->status, 200) << fine->body;
  ASSERT_EQ(standard->status, 200) << standard->body;
  EXPECT_EQ(fast->get_header_value("X-Penumbra-Samples"), "1");
  EXPECT_EQ(standard->get_header_value("X-Penumbra-Samples"), std::to_string(kDefaultImageSamples));
  EXPECT_NE(fast->body, fine->body);
  // A big image without `samples` gets what the budget allows (a view of nothing: cheap).
  const auto big = client.Get(
      ("/api/scenes/" + id + "/image?width=2048&height=1024&position=0,0,100&target=0,0,200")
          .c_str());
  ASSERT_EQ(big->status, 200) << big->body;
  EXPECT_EQ(big->get_header_value("X-Penumbra-Samples"), "8");
}

TEST(ImageMicrofacet, HostileSamplesAre400AndChangeNothing) {
  RunningServer running;
  const std::string id = running.addBundled("materials");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/image?width=64&height=64";
  for (const std::string value : {"0", "-1", "257", "abc", "1.5", "", "1e3",
                                  "99999999999999999999999", "4 ", "%00", "0x10", "+4"}) {
    const auto res = client.Get((base + "&samples=" + value).c_str());
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 400) << value << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], "query.samples") << value;
  }
  // Within [1, 256] but past the budget for this size: the message says the most allowed.
  const auto over =
      client.Get(("/api/scenes/" + id + "/image?width=4096&height=4096&samples=2").c_str());
  ASSERT_EQ(over->status, 400) << over->body;
  EXPECT_EQ(bodyJson(over)["error"]["path"], "query.samples");
  EXPECT_NE(bodyJson(over)["error"]["message"].get<std::string>().find("at most 1"),
            std::string::npos);
  const auto wide =
      client.Get(("/api/scenes/" + id + "/image?width=2048&height=2048&samples=5").c_str());
  ASSERT_EQ(wide->status, 400) << wide->body;
  EXPECT_NE(bodyJson(wide)["error"]["message"].get<std::string>().find("at most 4"),
            std::string::npos);
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 0);
}

TEST(ImageMicrofacet, ImagesRenderWhileEditsApply) {
  RunningServer running;
  const std::string id = running.addBundled("materials");
  const Scene scene = protocol::loadSceneFile(scenePath("materials"));
  std::atomic<bool> done{false};
  std::atomic<int> edits{0};
  std::thread editor([&] {
    auto client = running.client();
    for (int i = 0; i < 12; ++i) {
      const auto res =
          postJson(client, "/api/scenes/" + id + "/edits", moveJson(scene, -0.6 + 0.1 * i, 0.5));
      if (res && res->status == 200) ++edits;
    }
    done = true;
  });
  auto client = running.client();
  int images = 0;
  std::set<std::string> versions;
  while (!done || images < 3) {
    const auto res =
        client.Get(("/api/scenes/" + id + "/image?width=40&height=30&samples=1" + kView).c_str());
    ASSERT_TRUE(res);
    ASSERT_EQ(res->status, 200) << res->body;
    versions.insert(res->get_header_value("X-Penumbra-Version"));
    ++images;
  }
  editor.join();
  EXPECT_EQ(edits, 12);
  EXPECT_GE(images, 3);
  // The last version's image is still exactly the engine's.
  const auto last =
      client.Get(("/api/scenes/" + id + "/image?width=64&height=48&samples=2" + kView).c_str());
  std::vector<Frame> frames;
  for (int i = 0; i < 12; ++i) frames.push_back(moveGoldBox(scene, -0.6 + 0.1 * i, 0.5));
  EXPECT_TRUE(last->body == expectedPng(scene, frames, 64, 48, 2))
      << "differs from the engine's render";
}

}  // namespace
}  // namespace penumbra::server::test
