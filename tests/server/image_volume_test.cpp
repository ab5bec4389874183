// Volume objects over HTTP: GET /image draws the served scene's volume (the same bytes as the
// CLI's render of the file), a posted scene naming a volume file is refused at its key path
// with 422 and nothing created, and a journaled scene with a volume comes back after a restart.
#include <gtest/gtest.h>

#include "core/engine/engine.h"
#include "core/render/renderer.h"
#include "imageio/image_encoding.h"
#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {

const std::string kImage = "/image?width=48&height=40";

std::string expectedPng(const Scene& scene) {
  Engine engine(scene);
  RenderSettings settings;
  settings.width = 48;
  settings.height = 40;
  const std::vector<uint8_t> bytes = imageio::encodePng(render(engine.scene(), engine.mesh(), settings));
  return std::string(bytes.begin(), bytes.end());
}

TEST(ImageVolume, TheImageDrawsTheVolumeAsTheCliDoes) {
  RunningServer running;
  const std::string id = running.addBundled("volume_room");
  const Scene withVolume = protocol::loadSceneFile(scenePath("volume_room"));
  const Scene withoutVolume = protocol::loadSceneFile(scenePath("cornell"));
  auto client = running.client();
  const auto image = client.Get(("/api/scenes/" + id + kImage).c_str());
  ASSERT_EQ(image->status, 200) << image->body;
  EXPECT_TRUE(image->body == expectedPng(withVolume)) << "differs from the CLI's render";
  EXPECT_FALSE(image->body == expectedPng(withoutVolume)) << "the volume is missing";
}

TEST(ImageVolume, APostedSceneCannotNameAVolumeFile) {
  RunningServer running;
  auto client = running.client();
  json scene = json::parse(sceneText("cornell"));
  scene["objects"].push_back(
      {{"id", "v"}, {"type", "volume"}, {"file", "/etc/passwd"}, {"isovalue", 1}});
  const auto answer = postJson(client, "/api/scenes", scene);
  ASSERT_EQ(answer->status, 422) << answer->body;
  EXPECT_EQ(bodyJson(answer)["error"]["path"], "objects[7].file");
  const auto list = client.Get("/api/scenes");
  EXPECT_EQ(bodyJson(list)["scenes"].size(), 0u) << list->body;
}

TEST(ImageVolume, AJournaledVolumeSceneIsRestored) {
  TempDataDir data;
  std::string id, before;
  {
    RunningServer first(data.durable());
    id = first.addBundled("volume_room");
    auto client = first.client();
    before = client.Get(("/api/scenes/" + id + kImage).c_str())->body;
  }
  RunningServer second(data.durable());
  ASSERT_EQ(second.server().restore().size(), 1u);
  auto client = second.client();
  const auto after = client.Get(("/api/scenes/" + id + kImage).c_str());
  ASSERT_EQ(after->status, 200) << after->body;
  EXPECT_TRUE(after->body == before);
}

}  // namespace
}  // namespace penumbra::server::test
