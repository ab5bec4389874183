// Concurrent writers and readers over real HTTP: frames apply one at a time, versions
// count every frame, and a reader never sees a half-applied frame.
#include <gtest/gtest.h>

#include <map>
#include <mutex>

#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

// The smallest x of an object's receiver positions in a mesh JSON (a corner of its faces,
// so a rigid move by dx shifts it by exactly dx).
double minX(const json& mesh, const std::string& object) {
  double x = std::numeric_limits<double>::infinity();
  for (const json& r : mesh["receivers"])
    if (r["object"] == object)
      for (const json& p : r["positions"]) x = std::min(x, p[0].get<double>());
  return x;
}

TEST(ServerConcurrency, ReadersSeeWholeVersionsWhileTwoThreadsEdit) {
  RunningServer running;
  const std::string id = running.addBundled("cornell");
  const std::string base = "/api/scenes/" + id;
  const json scene = bodyJson(running.client().Get(base.c_str()))["scene"];
  json shortT, tallT;
  for (const json& o : scene["objects"]) {
    if (o["id"] == "short_block") shortT = o["transform"];
    if (o["id"] == "tall_block") tallT = o["transform"];
  }
  const json mesh0 = bodyJson(running.client().Get((base + "/mesh").c_str()));
  const double short0 = minX(mesh0, "short_block"), tall0 = minX(mesh0, "tall_block");

  // Each frame moves both blocks by the same dx: a half-applied frame would show them apart.
  constexpr int kWriters = 2, kFramesEach = 5;
  std::mutex mutex;
  std::map<uint64_t, double> dxOfVersion;  // from the writers' responses
  std::vector<std::pair<uint64_t, std::pair<double, double>>>
      seen;  // version → observed (dx short, dx tall)
  std::atomic<bool> writing{true};
  std::atomic<int> failures{0};

  auto writer = [&](int w) {
    auto client = running.client();
    for (int k = 0; k < kFramesEach; ++k) {
      const double dx = 0.01 * (1 + w * kFramesEach + k);
      json a = shortT, b = tallT;
      a["translate"][0] = shortT["translate"][0].get<double>() + dx;
      b["translate"][0] = tallT["translate"][0].get<double>() + dx;
      const json frame = {
          {"edits", json::array({{{"op", "move"}, {"id", "short_block"}, {"transform", a}},
                                 {{"op", "move"}, {"id", "tall_block"}, {"transform", b}}})}};
      const auto res = client.Post((base + "/edits").c_str(), frame.dump(), "application/json");
      if (!res || res->status != 200) {
        ++failures;
        continue;
      }
      std::lock_guard lock(mutex);
      dxOfVersion[json::parse(res->body)["version"].get<uint64_t>()] = dx;
    }
  };
  auto reader = [&] {
    auto client = running.client();
    uint64_t last = 0;
    while (writing) {
      const auto res = client.Get((base + "/mesh").c_str());
      if (!res || res->status != 200) {
        ++failures;
        continue;
      }
      const json mesh = json::parse(res->body);
      const uint64_t version = mesh["scene_version"];
      if (version < last) ++failures;  // versions never go back
      last = version;
      std::lock_guard lock(mutex);
      seen.push_back(
          {version, {minX(mesh, "short_block") - short0, minX(mesh, "tall_block") - tall0}});
    }
  };
  std::vector<std::thread> threads;
  for (int r = 0; r < 2; ++r) threads.emplace_back(reader);
  std::vector<std::thread> writers;
  for (int w = 0; w < kWriters; ++w) writers.emplace_back(writer, w);
  for (auto& t : writers) t.join();
  writing = false;
  for (auto& t : threads) t.join();

  EXPECT_EQ(failures, 0);
  // Every frame got its own version, 1..N.
  ASSERT_EQ(dxOfVersion.size(), size_t(kWriters * kFramesEach));
  EXPECT_EQ(dxOfVersion.begin()->first, 1u);
  EXPECT_EQ(dxOfVersion.rbegin()->first, uint64_t(kWriters * kFramesEach));
  ASSERT_FALSE(seen.empty());
  for (const auto& [version, dx] : seen) {
    const double expected = version == 0 ? 0.0 : dxOfVersion.at(version);
    EXPECT_NEAR(dx.first, expected, 1e-9) << "version " << version;
    EXPECT_NEAR(dx.second, expected, 1e-9) << "version " << version;
  }
  EXPECT_EQ(bodyJson(running.client().Get(base.c_str()))["version"], kWriters * kFramesEach);
}

}  // namespace
}  // namespace penumbra::server::test
