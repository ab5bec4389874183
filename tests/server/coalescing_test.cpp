// Group commit of edit frames over real HTTP (docs/API.md "Load"): frames of different clients
// that queue while a frame applies are applied together, as one version, each client still
// gets its own answer, a refused frame among them fails alone, and the served mesh is exact.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "core/reference/exact_irradiance.h"
#include "scenegen/dense_scene.h"
#include "server_fixture.h"

namespace penumbra::server::test {
namespace {

const std::string kEdits = "/api/scenes/dense/edits";

// A dense room of 15 floating boxes (nothing rests on anything, so the exact reference holds
// at every served vertex) whose first frame's meshing is held, so frames sent meanwhile queue.
struct SlowFirstFrame {
  RunningServer running;
  Scene scene = makeDenseScene({15, 3});
  SlowFirstFrame() : running(options()) { running.server().addScene(scene, "dense.scene.json", "dense"); }
  static ServerOptions options() {
    ServerOptions options = RunningServer::loopback();
    auto calls = std::make_shared<std::atomic<int>>(0);
    options.engine.failurePoint = [calls](const char* point) {
      if (std::string(point) == "meshing" && (*calls)++ == 0)
        std::this_thread::sleep_for(std::chrono::milliseconds(400));
    };
    return options;
  }
  // box_<i> slid by `dx` (boxes keep kDenseGap between their bounding spheres: < 5 mm never touches).
  json slide(int box, double dx) const {
    const Object& object = scene.objects()[*scene.findObject("box_" + std::to_string(box))];
    Transform moved = object.transform;
    moved.translate.x += dx;
    return {{"edits", json::array({{{"op", "move"},
                                    {"id", object.id},
                                    {"transform", protocol::transformToJson(moved)}}})}};
  }
};

struct CoalescedAnswer {
  int status = 0;
  json body;
};

// Sends `first`, then (while it applies) `others`, each on its own connection; returns the
// answers of `others` in order, then first's.
std::vector<CoalescedAnswer> sendTogether(RunningServer& running, const json& first, const std::vector<json>& others) {
  std::vector<CoalescedAnswer> answers(others.size() + 1);
  const auto send = [&](size_t slot, const json& frame) {
    TestClient client = running.client();
    const auto res = client.Post(kEdits.c_str(), frame.dump(), "application/json");
    if (res) answers[slot] = CoalescedAnswer{res->status, json::parse(res->body)};
  };
  std::thread alone(send, others.size(), first);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // `first` is applying
  std::vector<std::thread> threads;
  for (size_t i = 0; i < others.size(); ++i) threads.emplace_back(send, i, others[i]);
  alone.join();
  for (std::thread& t : threads) t.join();
  return answers;
}

json servedScene(RunningServer& running) { return bodyJson(running.client().Get("/api/scenes/dense")); }

double translateX(const json& served, const std::string& id) {
  for (const json& object : served["scene"]["objects"])
    if (object["id"] == id) return object["transform"]["translate"][0];
  return NAN;
}

// Served mesh vertices (every 5th) whose value differs from the exact reference for the served
// scene by more than the engine tests allow (1e-9 relative + 1e-12 of the peak).
size_t referenceMismatches(RunningServer& running) {
  const json served = servedScene(running);
  const json mesh = bodyJson(running.client().Get("/api/scenes/dense/mesh"));
  EXPECT_EQ(mesh["scene_version"], served["version"]);
  const Scene scene = protocol::sceneFromJson(served["scene"]);
  const ExactReference reference(scene);
  double peak = 0;
  for (const json& r : mesh["receivers"])
    for (const json& e : r["irradiance"]) peak = std::max(peak, e[1].get<double>());
  size_t errors = 0, index = 0, checked = 0;
  for (const json& r : mesh["receivers"]) {
    const json& n = r["normal"];
    const Vec3 normal{n[0].get<double>(), n[1].get<double>(), n[2].get<double>()};
    for (size_t v = 0; v < r["positions"].size(); ++v) {
      if (index++ % 5) continue;
      const json& q = r["positions"][v];
      const PointIrradiance truth =
          reference.evaluate({q[0].get<double>(), q[1].get<double>(), q[2].get<double>()}, normal);
      ++checked;
      for (int c = 0; c < 3; ++c) {
        const double value = r["irradiance"][v][c].get<double>();
        if (std::abs(value - truth.irradiance[c]) > 1e-9 * std::abs(truth.irradiance[c]) + 1e-12 * peak) {
          if (errors++ < 3)
            ADD_FAILURE() << r["object"] << "/" << r["face"] << " vertex " << v << ": served " << value
                          << ", reference " << truth.irradiance[c];
          break;
        }
      }
    }
  }
  EXPECT_GT(checked, 300u);
  return errors;
}

TEST(Coalescing, FramesThatQueuedTogetherAreOneVersionAndAllApplyExactly) {
  SlowFirstFrame server;
  ASSERT_EQ(referenceMismatches(server.running), 0u);  // the check holds before any edit
  std::vector<json> frames;
  for (int box = 1; box <= 5; ++box) frames.push_back(server.slide(box, 0.001 * box));
  const std::vector<CoalescedAnswer> answers = sendTogether(server.running, server.slide(0, 0.004), frames);
  ASSERT_EQ(answers.back().status, 200);  // box_0's, alone
  EXPECT_EQ(answers.back().body["version"], 1);
  EXPECT_EQ(answers.back().body["coalesced_frames"], 1);
  for (size_t i = 0; i < frames.size(); ++i) {
    ASSERT_EQ(answers[i].status, 200) << i << ": " << answers[i].body.dump();
    EXPECT_EQ(answers[i].body["version"], 2) << i;  // all queued behind box_0: one batch
    EXPECT_EQ(answers[i].body["coalesced_frames"], frames.size()) << i;
  }
  // Every box is where its own frame put it, and the served mesh is exact.
  const json served = servedScene(server.running);
  EXPECT_EQ(served["version"], 2);
  for (int box = 0; box <= 5; ++box) {
    const std::string id = "box_" + std::to_string(box);
    const double dx = box == 0 ? 0.004 : 0.001 * box;
    EXPECT_EQ(translateX(served, id), server.scene.objects()[*server.scene.findObject(id)].transform.translate.x + dx)
        << id;
  }
  EXPECT_EQ(referenceMismatches(server.running), 0u);
}

TEST(Coalescing, ARefusedFrameInABatchFailsAloneWithItsOwnPath) {
  SlowFirstFrame server;
  json unknown = server.slide(2, 0.001);
  unknown["edits"][0]["id"] = "no_such_box";
  const std::vector<CoalescedAnswer> answers =
      sendTogether(server.running, server.slide(0, 0.001), {server.slide(1, 0.002), unknown, server.slide(2, 0.003)});
  ASSERT_EQ(answers[0].status, 200) << answers[0].body.dump();
  ASSERT_EQ(answers[2].status, 200) << answers[2].body.dump();
  ASSERT_EQ(answers[1].status, 422) << answers[1].body.dump();
  EXPECT_EQ(answers[1].body["error"]["path"], "edits[0].id");
  EXPECT_EQ(answers[1].body["error"]["edit"], 0);
  // The batch was refused as a whole, then the two good frames went in one by one.
  EXPECT_EQ(answers[0].body["coalesced_frames"], 1);
  EXPECT_EQ(servedScene(server.running)["version"], 3);
}

TEST(Coalescing, FramesOnTheSameObjectAreAppliedOneByOne) {
  SlowFirstFrame server;
  const std::vector<CoalescedAnswer> answers =
      sendTogether(server.running, server.slide(0, 0.001), {server.slide(1, 0.001), server.slide(1, 0.003)});
  ASSERT_EQ(answers[0].status, 200);
  ASSERT_EQ(answers[1].status, 200);
  EXPECT_EQ(answers[0].body["coalesced_frames"], 1);
  EXPECT_EQ(answers[1].body["coalesced_frames"], 1);
  ASSERT_NE(answers[0].body["version"], answers[1].body["version"]);
  // The later version's move is where the box is.
  const bool secondLast = answers[1].body["version"] > answers[0].body["version"];
  const json served = servedScene(server.running);
  EXPECT_EQ(served["version"], 3);
  EXPECT_EQ(translateX(served, "box_1"),
            server.scene.objects()[*server.scene.findObject("box_1")].transform.translate.x + (secondLast ? 0.003 : 0.001));
}

}  // namespace
}  // namespace penumbra::server::test
