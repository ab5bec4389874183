// GET /image with gi=sensors: the route's image equals an in-process render with the same GI
// settings byte for byte, reports its sensors, and refuses hostile GI parameters with the key
// path (changing nothing).
#include <gtest/gtest.h>

#include "core/engine/engine.h"
#include "core/render/renderer.h"
#include "imageio/image_encoding.h"
#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

TEST(ImageGi, SensorsImageEqualsTheInProcessRenderAndDiffersFromDirectLight) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/image?width=40&height=40&samples=1";
  const auto direct = client.Get(base.c_str());
  const auto bounced = client.Get((base + "&gi=sensors&sensor_size=16&tile=8&bounces=2").c_str());
  ASSERT_TRUE(direct && bounced) << "no answer: " << httplib::to_string(direct.error()) << ", "
                                 << httplib::to_string(bounced.error());
  ASSERT_EQ(direct->status, 200) << direct->body;
  ASSERT_EQ(bounced->status, 200) << bounced->body;
  EXPECT_NE(direct->body, bounced->body);
  EXPECT_FALSE(direct->has_header("X-Penumbra-Gi-Sensors"));
  EXPECT_GT(std::stoul(bounced->get_header_value("X-Penumbra-Gi-Sensors")), 0u);

  Engine engine(protocol::loadSceneFile(scenePath("cornell")));
  RenderSettings settings;
  settings.width = settings.height = 40;
  settings.microfacet.pathsPerPixel = 1;
  settings.microfacet.lightSamples = 4;
  gi::GiSettings gi;
  gi.sensorSize = 16;
  gi.placement.tile = 8;
  gi.bounces = 2;
  settings.gi = gi;
  const std::vector<uint8_t> expected = imageio::encodePng(render(engine.scene(), engine.mesh(), settings));
  EXPECT_EQ(bounced->body, std::string(expected.begin(), expected.end()));
}

TEST(ImageGi, HostileGiParametersAre400WithTheirPathAndChangeNothing) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  auto client = running.client();
  const std::string base = "/api/scenes/" + id + "/image?width=32&height=32";
  const std::pair<std::string, std::string> cases[] = {
      {"&gi=photons", "query.gi"},
      {"&gi=", "query.gi"},
      {"&gi=%ff", "query.gi"},
      {"&gi=sensors&sensor_size=0", "query.sensor_size"},
      {"&gi=sensors&sensor_size=65", "query.sensor_size"},
      {"&gi=sensors&sensor_size=abc", "query.sensor_size"},
      {"&gi=sensors&tile=0", "query.tile"},
      {"&gi=sensors&tile=-4", "query.tile"},
      {"&gi=sensors&threshold=-1", "query.threshold"},
      {"&gi=sensors&threshold=nan", "query.threshold"},
      {"&gi=sensors&threshold=1e400", "query.threshold"},
      {"&gi=sensors&bounces=0", "query.bounces"},
      {"&gi=sensors&bounces=5", "query.bounces"},
      {"&gi=sensors&filter=17", "query.filter"},
      {"&sensor_size=8", "query.sensor_size"},  // a GI setting without gi=sensors
      {"&gi=none&bounces=2", "query.bounces"},
  };
  for (const auto& [query, path] : cases) {
    const auto res = client.Get((base + query).c_str());
    ASSERT_TRUE(res) << query;
    EXPECT_EQ(res->status, 400) << query << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << query;
  }
  // Past the ray budget: 4096² pixels with 32² sensors.
  const auto big = client.Get(("/api/scenes/" + id + "/image?width=4096&height=4096&samples=1&gi=sensors").c_str());
  ASSERT_EQ(big->status, 400) << big->body;
  EXPECT_EQ(bodyJson(big)["error"]["path"], "query.sensor_size");
  EXPECT_EQ(bodyJson(client.Get(("/api/scenes/" + id).c_str()))["version"], 0);
}

}  // namespace
}  // namespace penumbra::server::test
