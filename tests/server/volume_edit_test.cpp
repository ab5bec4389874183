// Volume edits over HTTP (issue 15, the page's part): `move` and `set_volume` on a served volume,
// POST .../volumes uploading a NRRD, and add_volume / remove as undo and redo. Each is one
// version with no DM work, changes the server's image, is refused whole with the key path when
// any edit is bad, and comes back after a restart from the journal.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "protocol/json_text.h"
#include "server_fixture.h"
#include "temp_data_dir.h"

namespace penumbra::server::test {
namespace {

const std::string kImage = "/image?width=48&height=40";
const std::string kBase = "/api/scenes/volume_room";

std::string smokeBytes() {
  return protocol::readTextFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/volumes/smoke64.nrrd",
                                size_t(1) << 24);
}

json frame(const json& edit) { return {{"edits", json::array({edit})}}; }

json setVolume(const std::string& id, const json& isovalue) {
  return frame({{"op", "set_volume"}, {"id", id}, {"isovalue", isovalue}});
}

json moveVolume(double x) {
  return frame({{"op", "move"},
                {"id", "smoke"},
                {"transform", {{"translate", {x, 1.0, 3.3}}, {"scale", {2.1, 2.1, 2.1}}}}});
}

json volumeJson(TestClient& client, const std::string& id) {
  const json wrapped = bodyJson(client.Get(kBase.c_str()));
  for (const json& object : wrapped["scene"]["objects"])
    if (object["id"] == id) return object;
  return nullptr;
}

std::string image(TestClient& client) {
  const auto res = client.Get((kBase + kImage).c_str());
  EXPECT_EQ(res->status, 200) << res->body;
  return res->body;
}

TEST(VolumeEdits, MoveAndIsovalueAreVersionsThatChangeTheImageNotTheMesh) {
  RunningServer running;
  running.addBundled("volume_room");
  auto client = running.client();
  const std::string mesh0 = client.Get((kBase + "/mesh?format=bin").c_str())->body;
  const std::string image0 = image(client);

  const auto moved = postJson(client, kBase + "/edits", moveVolume(1.2));
  ASSERT_EQ(moved->status, 200) << moved->body;
  const json result = bodyJson(moved);
  EXPECT_EQ(result["version"], 1);
  EXPECT_EQ(result["changed_receivers_count"], 0) << "a volume is no DM occluder";
  EXPECT_TRUE(result["mesh_changed"].empty());
  EXPECT_EQ(volumeJson(client, "smoke")["transform"]["translate"][0], 1.2);
  const std::string image1 = image(client);
  EXPECT_TRUE(image1 != image0) << "the image shows the moved volume";

  const auto iso = postJson(client, kBase + "/edits", setVolume("smoke", 90.5));
  ASSERT_EQ(iso->status, 200) << iso->body;
  EXPECT_EQ(bodyJson(iso)["version"], 2);
  EXPECT_EQ(volumeJson(client, "smoke")["isovalue"], 90.5);
  EXPECT_TRUE(image(client) != image1) << "the image shows the new isosurface";
  EXPECT_EQ(client.Get((kBase + "/mesh?format=bin").c_str())->body.substr(12), mesh0.substr(12))
      << "the DM mesh is the same but for its version";

  // Back: the same image as at the start (nothing else moved).
  ASSERT_EQ(postJson(client, kBase + "/edits", setVolume("smoke", 40.5))->status, 200);
  ASSERT_EQ(postJson(client, kBase + "/edits", moveVolume(0.35))->status, 200);
  EXPECT_TRUE(image(client) == image0);
}

TEST(VolumeEdits, BadVolumeEditsAreRefusedWholeWithTheKeyPath) {
  RunningServer running;
  running.addBundled("volume_room");
  auto client = running.client();
  const json before = bodyJson(client.Get(kBase.c_str()));
  const json goodMove = moveVolume(1.0)["edits"][0];
  const std::vector<std::pair<json, std::string>> cases = {
      {setVolume("smoke", 1e9), "edits[0].isovalue"},  // outside the data's values
      {setVolume("smoke", -1), "edits[0].isovalue"},
      {setVolume("smoke", "nan"), "edits[0].isovalue"},  // not a number
      {setVolume("smoke", nullptr), "edits[0].isovalue"},
      {setVolume("ghost", 50), "edits[0].id"},       // unknown volume
      {setVolume("tall_block", 50), "edits[0].id"},  // a polygon object
      {frame({{"op", "move"}, {"id", "smoke"}, {"transform", {{"scale", {0, 1, 1}}}}}),
       "edits[0].transform.scale"},
      // The first edit is fine; the second is not: nothing of the frame is applied.
      {{{"edits", {goodMove, {{"op", "set_volume"}, {"id", "smoke"}, {"isovalue", 1e9}}}}},
       "edits[1].isovalue"},
      {{{"edits", {goodMove, {{"op", "remove"}, {"id", "smoke"}}, goodMove}}}, "edits[2].id"},
      // A client's frame cannot make the server open a file it does not hold.
      {frame({{"op", "add_volume"},
              {"volume",
               {{"id", "v"}, {"type", "volume"}, {"file", "/etc/passwd"}, {"isovalue", 1}}}}),
       "edits[0].volume.file"},
      {frame({{"op", "add_volume"},
              {"volume",
               {{"id", "v"}, {"type", "volume"}, {"file", "../../etc/passwd"}, {"isovalue", 1}}}}),
       "edits[0].volume.file"},
      {frame({{"op", "add"},
              {"object",
               {{"id", "smoke"},
                {"vertices", {{0, 0, 0}, {1, 0, 0}, {0, 0, 1}}},
                {"faces", {{0, 2, 1}}}}}}),
       "edits[0].object.id"},  // a volume has that id
  };
  for (const auto& [body, path] : cases) {
    const auto res = postJson(client, kBase + "/edits", body);
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, 422) << body.dump() << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << body.dump() << " → " << res->body;
  }
  const json after = bodyJson(client.Get(kBase.c_str()));
  EXPECT_EQ(after["version"], 0);
  EXPECT_EQ(after["scene"], before["scene"]);
}

TEST(VolumeEdits, RemoveThenAddBackIsTheUndoOfADelete) {
  RunningServer running;
  running.addBundled("volume_room");
  auto client = running.client();
  const std::string image0 = image(client);
  const json smoke = volumeJson(client, "smoke");
  ASSERT_EQ(postJson(client, kBase + "/edits", frame({{"op", "remove"}, {"id", "smoke"}}))->status,
            200);
  EXPECT_TRUE(volumeJson(client, "smoke").is_null());
  EXPECT_TRUE(image(client) != image0);
  // The scene's own file (as GET scene names it) may be added back by a client's frame.
  const auto back =
      postJson(client, kBase + "/edits", frame({{"op", "add_volume"}, {"volume", smoke}}));
  ASSERT_EQ(back->status, 200) << back->body;
  EXPECT_EQ(volumeJson(client, "smoke"), smoke);
  EXPECT_TRUE(image(client) == image0);
}

TEST(VolumeEdits, AnUploadedVolumeIsAddedMovedAndRestoredAfterARestart) {
  TempDataDir data;
  std::string image2, scene2;
  {
    RunningServer first(data.durable());
    first.addBundled("volume_room");
    auto client = first.client();
    const std::string image0 = image(client);
    const auto up =
        client.Post((kBase + "/volumes?id=puff&isovalue=60&translate=2.2,1.5,2").c_str(),
                    smokeBytes(), "application/octet-stream");
    ASSERT_EQ(up->status, 201) << up->body;
    const json answer = bodyJson(up);
    EXPECT_EQ(answer["version"], 1);
    EXPECT_EQ(answer["volume"]["id"], "puff");
    EXPECT_EQ(answer["volume"]["size"], json({64, 64, 64}));
    EXPECT_EQ(answer["volume"]["voxel_type"], "uchar");
    const json puff = volumeJson(client, "puff");
    ASSERT_FALSE(puff.is_null());
    EXPECT_EQ(puff["isovalue"], 60);
    EXPECT_TRUE(std::filesystem::exists(puff["file"].get<std::string>()));
    EXPECT_EQ(bodyJson(client.Get(kBase.c_str()))["volumes"].size(), 2u);
    EXPECT_TRUE(image(client) != image0);
    ASSERT_EQ(postJson(client, kBase + "/edits", setVolume("puff", 80))->status, 200);
    const json move =
        frame({{"op", "move"}, {"id", "puff"}, {"transform", {{"translate", {1.5, 0.2, 1}}}}});
    ASSERT_EQ(postJson(client, kBase + "/edits", move)->status, 200);
    // Undo of the upload, then redo by add_volume naming the file the server kept.
    ASSERT_EQ(postJson(client, kBase + "/edits", frame({{"op", "remove"}, {"id", "puff"}}))->status,
              200);
    json again = puff;
    again["isovalue"] = 80;
    again["transform"] = {{"translate", {1.5, 0.2, 1}}};
    const auto redo =
        postJson(client, kBase + "/edits", frame({{"op", "add_volume"}, {"volume", again}}));
    ASSERT_EQ(redo->status, 200) << redo->body;
    image2 = image(client);
    scene2 = bodyJson(client.Get(kBase.c_str())).dump();
    EXPECT_EQ(bodyJson(client.Get(kBase.c_str()))["version"], 5);
  }
  RunningServer second(data.durable());
  const auto restored = second.server().restore();
  ASSERT_EQ(restored.size(), 1u);
  EXPECT_TRUE(restored[0].served) << restored[0].problem;
  auto client = second.client();
  EXPECT_EQ(bodyJson(client.Get(kBase.c_str())).dump(), scene2);
  EXPECT_TRUE(image(client) == image2);
}

TEST(VolumeEdits, BadUploadsCreateNothing) {
  TempDataDir data;
  RunningServer running(data.durable());
  running.addBundled("volume_room");
  auto client = running.client();
  const std::string type = "application/octet-stream";
  const std::string huge =
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 1024 1024 1024\nencoding: raw\n\nabc";
  const std::string truncated =
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 4\nencoding: raw\n\nabc";
  const std::string flat =
      "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4 1\nencoding: raw\n\n" + std::string(16, 'a');
  const std::vector<std::tuple<std::string, std::string, int, std::string>> cases = {
      {"", "", 400, "(body)"},
      {"", "not a volume at all", 422, "(body)"},
      {"", huge, 422, "(body)"},       // resource limit, read from the header alone
      {"", truncated, 422, "(body)"},  // Teem: the data is short
      {"", flat, 422, "(body)"},       // a side of one voxel
      {"?isovalue=nan", smokeBytes(), 400, "query.isovalue"},
      {"?isovalue=1e9", smokeBytes(), 400, "query.isovalue"},
      {"?id=smoke", smokeBytes(), 400, "query.id"},       // taken by a volume
      {"?id=tall_block", smokeBytes(), 400, "query.id"},  // taken by a polygon object
      {"?material=gold", smokeBytes(), 400, "query.material"},
      {"?translate=1,2", smokeBytes(), 400, "query.translate"},
  };
  for (const auto& [query, body, status, path] : cases) {
    const auto res = client.Post((kBase + "/volumes" + query).c_str(), body, type.c_str());
    ASSERT_TRUE(res);
    EXPECT_EQ(res->status, status) << query << " → " << res->body;
    EXPECT_EQ(bodyJson(res)["error"]["path"], path) << query << " → " << res->body;
  }
  const json after = bodyJson(client.Get(kBase.c_str()));
  EXPECT_EQ(after["version"], 0);
  EXPECT_EQ(after["volumes"].size(), 1u);
  const std::filesystem::path uploads = std::filesystem::path(data.str()) / "volumes";
  if (std::filesystem::exists(uploads)) {
    EXPECT_TRUE(std::filesystem::is_empty(uploads)) << "a refused upload leaves no file";
  }
}

// Two volume rooms on one durable server: "volume_room" (kBase) and `other`, whose id starts
// with the first's.
struct TwoVolumeRooms {
  TempDataDir data;
  RunningServer running{data.durable()};
  std::string other;
  TwoVolumeRooms() {
    running.addBundled("volume_room");
    other = running.server().addScene(protocol::loadSceneFile(scenePath("volume_room")), "volume_room-2",
                                      "volume_room-2");
  }
  // Uploads the smoke volume to scene `id` as "puff".
  void upload(TestClient& client, const std::string& id) {
    const auto up = client.Post(("/api/scenes/" + id + "/volumes?id=puff").c_str(), smokeBytes(),
                                "application/octet-stream");
    ASSERT_TRUE(up);
    ASSERT_EQ(up->status, 201) << up->body;
  }
};

// Deleting a scene deletes the volumes uploaded to it (the journal no longer names them); another
// scene's uploads stay, even when its id starts with the deleted one's.
TEST(VolumeEdits, DeletingASceneDeletesItsUploads) {
  TwoVolumeRooms rooms;
  const TempDataDir& data = rooms.data;
  const std::string& other = rooms.other;
  auto client = rooms.running.client();
  for (const std::string& id : {std::string("volume_room"), other}) ASSERT_NO_FATAL_FAILURE(rooms.upload(client, id));
  const std::filesystem::path uploads = std::filesystem::path(data.str()) / "volumes";
  const auto files = [&] {
    return std::distance(std::filesystem::directory_iterator(uploads),
                         std::filesystem::directory_iterator());
  };
  EXPECT_EQ(files(), 2);
  EXPECT_EQ(client.Delete(kBase.c_str())->status, 204);
  EXPECT_EQ(files(), 1);
  for (const auto& entry : std::filesystem::directory_iterator(uploads))
    EXPECT_EQ(entry.path().filename().string().rfind(other + "-", 0), 0u);
}

// An upload is kept with its own scene (deleted with it; fetched with it by the node that serves
// it next): another scene's frame may not add it, and the scene's own frame may add it back.
TEST(VolumeEdits, AFrameMayAddOnlyItsOwnScenesUploads) {
  TwoVolumeRooms rooms;
  const std::string& other = rooms.other;
  auto client = rooms.running.client();
  ASSERT_NO_FATAL_FAILURE(rooms.upload(client, other));
  const json scene = bodyJson(client.Get(("/api/scenes/" + other).c_str()));
  json puff;
  for (const json& object : scene["scene"]["objects"])
    if (object["id"] == "puff") puff = object;
  ASSERT_TRUE(puff.is_object()) << scene.dump().substr(0, 300);
  const auto taken =
      postJson(client, kBase + "/edits", frame({{"op", "add_volume"}, {"volume", puff}}));
  EXPECT_EQ(taken->status, 422) << taken->body;
  EXPECT_EQ(bodyJson(taken)["error"]["path"], "edits[0].volume.file");
  EXPECT_TRUE(volumeJson(client, "puff").is_null());
  const std::string otherEdits = "/api/scenes/" + other + "/edits";
  ASSERT_EQ(postJson(client, otherEdits, frame({{"op", "remove"}, {"id", "puff"}}))->status, 200);
  const auto back = postJson(client, otherEdits, frame({{"op", "add_volume"}, {"volume", puff}}));
  EXPECT_EQ(back->status, 200) << back->body;
}

// A kill between storing an upload and committing its frame leaves a file no acknowledged
// version names; the next start removes it (and only it: the journaled upload restores).
TEST(VolumeEdits, AnUploadNoFrameNamesIsRemovedAtStart) {
  TempDataDir data;
  const std::filesystem::path uploads = std::filesystem::path(data.str()) / "volumes";
  {
    RunningServer running(data.durable());
    running.addBundled("volume_room");
    auto client = running.client();
    const auto up =
        client.Post((kBase + "/volumes?id=puff").c_str(), smokeBytes(), "application/octet-stream");
    ASSERT_TRUE(up);
    ASSERT_EQ(up->status, 201) << up->body;
  }
  ASSERT_EQ(std::distance(std::filesystem::directory_iterator(uploads),
                          std::filesystem::directory_iterator()),
            1);
  const std::filesystem::path kept = std::filesystem::directory_iterator(uploads)->path();
  const std::filesystem::path orphan = uploads / "volume_room-00000000deadbeef.nrrd";
  const std::filesystem::path foreign = uploads / "notes.txt";  // not an upload's name: left alone
  std::filesystem::copy_file(kept, orphan);
  std::ofstream(foreign) << "mine";
  RunningServer restarted(data.durable());
  restarted.server().restore();
  EXPECT_FALSE(std::filesystem::exists(orphan));
  EXPECT_TRUE(std::filesystem::exists(kept));
  EXPECT_TRUE(std::filesystem::exists(foreign));
  auto client = restarted.client();
  const auto scene = bodyJson(client.Get(kBase.c_str()));
  EXPECT_EQ(scene["version"], 1);
  EXPECT_EQ(scene["volumes"].size(), 2u) << scene.dump().substr(0, 300);
}

TEST(VolumeEdits, AnUploadPastTheBodyLimitIs413) {
  ServerOptions options = RunningServer::loopback();
  options.maxBodyBytes = 1024;  // smoke64.nrrd is 32 KB
  RunningServer running(options);
  running.addBundled("volume_room");
  auto client = running.client();
  const auto up =
      client.Post((kBase + "/volumes").c_str(), smokeBytes(), "application/octet-stream");
  ASSERT_TRUE(up);
  EXPECT_EQ(up->status, 413) << up->body;
  EXPECT_EQ(bodyJson(client.Get(kBase.c_str()))["version"], 0);
}

TEST(VolumeEdits, AFormUploadTakesItsIdFromTheFileName) {
  RunningServer running;
  running.addBundled("volume_room");
  auto client = running.client();
  const httplib::MultipartFormDataItems form = {
      {"file", smokeBytes(), "CT head.nrrd", "application/octet-stream"}};
  const auto up = client.Post((kBase + "/volumes").c_str(), form);
  ASSERT_EQ(up->status, 201) << up->body;
  EXPECT_EQ(bodyJson(up)["volume"]["id"], "CT_head");
  EXPECT_EQ(bodyJson(up)["volume"]["isovalue"], 127.5) << "the middle of the values by default";
  const auto again = client.Post((kBase + "/volumes").c_str(), form);
  ASSERT_EQ(again->status, 201) << again->body;
  EXPECT_EQ(bodyJson(again)["volume"]["id"], "CT_head-2") << "a taken name is numbered";
  const httplib::MultipartFormDataItems other = {
      {"data", smokeBytes(), "x.nrrd", "application/octet-stream"}};
  const auto bad = client.Post((kBase + "/volumes").c_str(), other);
  EXPECT_EQ(bad->status, 400);
  EXPECT_EQ(bodyJson(bad)["error"]["path"], "(form).data");
  EXPECT_EQ(bodyJson(client.Get(kBase.c_str()))["version"], 2);
}

TEST(VolumeEdits, APreviewFollowsTheIsovalue) {
  RunningServer running;
  running.addBundled("volume_room");
  auto client = running.client();
  const json low = bodyJson(client.Get((kBase + "/volumes/smoke/preview?isovalue=20").c_str()));
  const json high = bodyJson(client.Get((kBase + "/volumes/smoke/preview?isovalue=120").c_str()));
  ASSERT_GT(low["points"].size(), 0u);
  EXPECT_EQ(low["points"].size() % 3, 0u);
  EXPECT_NE(low["points"].size(), high["points"].size());
  EXPECT_EQ(client.Get((kBase + "/volumes/ghost/preview").c_str())->status, 404);
  EXPECT_EQ(bodyJson(client.Get(
                (kBase + "/volumes/smoke/preview?isovalue=1e9").c_str()))["error"]["path"],
            "query.isovalue");
}

}  // namespace
}  // namespace penumbra::server::test
