// The served mesh after edits, as a client following it sees it: the whole mesh at
// version 0, then each frame's `since` delta applied (listed receivers replaced, values-only
// ones given their new irradiance, removed ones dropped) gives byte-identical receiver JSON to
// a fresh mesh() of an engine given the same frames, moves and light radiance changes mixed. A
// radiance edit sends values, not geometry. Also gzip Content-Encoding of the binary mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <random>
#include <sstream>
#include <tuple>

#include "protocol/mesh_json.h"
#include "scenegen/cubes_scene.h"
#include "scenegen/model_scene.h"
#include "server/gzip_encoding.h"
#include "server/mesh_binary.h"
#include "server/scene_session.h"
#include "tests/server/binary_mesh_reader.h"
#include "tests/server/server_fixture.h"

namespace penumbra::server {
namespace {

using nlohmann::json;
using test::BinaryMesh;
using test::parseBinary;

// Receiver JSON by "object/face", without the served-only "scene_version".
std::map<std::string, std::string> receiverTextsByKey(const json& mesh) {
  std::map<std::string, std::string> out;
  for (json r : mesh["receivers"]) {
    r.erase("scene_version");
    out[r["object"].get<std::string>() + "/" + std::to_string(r["face"].get<int>())] = r.dump();
  }
  return out;
}

// The served mesh JSON of a selection, as a client parses it.
json meshJson(const SceneSnapshot& snapshot, const MeshSelection& selection) {
  std::ostringstream text;
  snapshot.writeMeshJson(text, selection);
  return json::parse(text.str());
}

// A set_light of the scene's first light: its radiance brighter or dimmer, half the time in
// another colour too.
Edit radianceEdit(const Scene& scene, std::mt19937_64& rng) {
  const Light& light = scene.lights().at(0);
  std::uniform_real_distribution<double> factor(0.5, 1.5);
  Edit edit;
  edit.op = Edit::Op::SetLight;
  edit.id = light.id;
  Vec3 radiance = light.radiance * factor(rng);
  if (rng() % 2) radiance = Vec3(radiance.x * factor(rng), radiance.y, radiance.z * factor(rng));
  edit.radiance = radiance;
  return edit;
}

// A frame like a drag (small moves of one cube), sometimes another cube too, an
// added cube, or removing the one added before; every third frame a light's radiance alone,
// and now and then a radiance change with the moves.
Frame randomFrame(const Scene& scene, std::mt19937_64& rng, int step, bool& added) {
  Frame frame;
  if (step % 3 == 2) return Frame{{radianceEdit(scene, rng)}};
  if (step % 7 == 3) frame.edits.push_back(radianceEdit(scene, rng));
  auto moveOf = [&](const std::string& id, double dx, double dz, double turn) {
    const size_t index = *scene.findObject(id);
    Edit edit;
    edit.op = Edit::Op::Move;
    edit.id = id;
    edit.transform = scene.objects()[index].transform;
    edit.transform.translate.x += dx;
    edit.transform.translate.z += dz;
    edit.transform.rotateDeg.y += turn;
    return edit;
  };
  std::uniform_real_distribution<double> small(-0.08, 0.08);
  frame.edits.push_back(moveOf("cube_0", small(rng), small(rng), 0));
  if (step % 4 == 1) frame.edits.push_back(moveOf("cube_1", small(rng), small(rng), 10));
  if (step % 5 == 2) {
    Edit edit;
    if (!added) {
      edit.op = Edit::Op::Add;
      edit.object = scene.objects()[*scene.findObject("cube_2")];
      edit.object.id = "cube_extra";
      edit.object.transform.translate.x += 0.5;
      edit.object.transform.translate.z += 0.25;
    } else {
      edit.op = Edit::Op::Remove;
      edit.id = "cube_extra";
    }
    added = !added;
    frame.edits.push_back(edit);
  }
  return frame;
}

Scene eightCubes() {
  CubesSceneOptions options;
  options.cubes = 8;
  options.seed = 4;
  return makeCubesScene(options);
}

TEST(MeshDelta, DeltasAppliedToTheWholeMeshEqualAFreshMeshAfterEachFrame) {
  const Scene scene = eightCubes();
  SceneSession session("t", "cubes8", scene);
  Engine reference(scene);
  const auto first = session.snapshot();
  std::map<std::string, std::string> held = receiverTextsByKey(meshJson(*first, first->select(std::nullopt)));

  std::mt19937_64 rng(17);
  bool added = false;
  size_t meshed = 0, receivers = 0, reused = 0, lit = 0, valuesOnly = 0;
  for (int step = 0; step < 12; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const Frame frame = randomFrame(reference.scene(), rng, step, added);
    const SceneSession::Applied applied = session.apply(frame);
    // The session casts afresh the changed trees that are mostly dead slots; so does the reference.
    reference.compactTrees(reference.apply(frame).changedReceivers);
    if (!applied.result.radianceChanged) {  // a radiance change sums every receiver again
      meshed += applied.meshedReceivers;
      receivers += applied.snapshot->receiverCount();
      reused += applied.meshCells.cellsReused;
      lit += applied.meshCells.cellsLit;
    }

    const SceneSnapshot& s = *applied.snapshot;
    const json delta = meshJson(s, s.select(s.version - 1));
    EXPECT_EQ(delta["version"], 2);
    for (json r : delta["receivers"]) {
      const std::string key =
          r["object"].get<std::string>() + "/" + std::to_string(r["face"].get<int>());
      r.erase("scene_version");
      if (r.contains("positions")) {
        held[key] = r.dump();
        continue;
      }
      // Values only: the held receiver's shape with the new irradiance.
      EXPECT_EQ(r.size(), 3u) << r.dump().substr(0, 200);
      ASSERT_TRUE(held.count(key)) << key;
      json receiver = json::parse(held.at(key));
      ASSERT_EQ(receiver["irradiance"].size(), r["irradiance"].size()) << key;
      receiver["irradiance"] = r["irradiance"];
      held[key] = receiver.dump();
      ++valuesOnly;
    }
    for (const json& gone : delta["removed"])
      held.erase(gone["object"].get<std::string>() + "/" + std::to_string(gone["face"].get<int>()));

    reference.forgetMeshMemo();
    const json fresh = protocol::meshToJson(reference.scene(), reference.mesh(), "cubes8");
    const auto want = receiverTextsByKey(fresh);
    ASSERT_EQ(held.size(), want.size());
    for (const auto& [key, text] : want) {
      ASSERT_TRUE(held.count(key)) << key;
      EXPECT_EQ(held.at(key), text) << key;
    }
    // The served whole mesh is that fresh mesh too.
    EXPECT_EQ(receiverTextsByKey(meshJson(s, s.select(std::nullopt))), want);
    if (HasFailure()) return;
  }
  // Dragging one cube re-meshes a few receivers, not the scene, and of their cells
  // most are replayed from the memo.
  EXPECT_LT(meshed * 2, receivers);
  EXPECT_GT(reused, lit);
  EXPECT_GT(valuesOnly, 0u);  // radiance changes were sent as values
}

// The binary form's view: parts. Following each frame's part delta (changed parts
// replaced, removed ones dropped) holds exactly a fresh engine's chunks, and a drag
// sends only some of the floor's chunks.
TEST(MeshDelta, PartDeltasAppliedToTheWholeMeshEqualAFreshEnginesChunks) {
  const Scene scene = eightCubes();
  SceneSession session("t", "cubes8", scene);
  Engine reference(scene);
  auto contentOf = [](const ReceiverMesh& m) {
    return std::tuple(m.positions, m.irradiance, m.classes, m.triangles, m.normal);
  };
  using Content = decltype(contentOf(std::declval<ReceiverMesh>()));
  std::map<PartKey, Content> held;
  {
    const auto first = session.snapshot();
    for (size_t i : first->select(std::nullopt).parts) held[first->parts[i].key] = contentOf(*first->parts[i].mesh);
  }
  std::mt19937_64 rng(29);
  bool added = false;
  size_t floorSent = 0, floorHeld = 0, valueParts = 0;
  for (int step = 0; step < 12; ++step) {
    SCOPED_TRACE("step " + std::to_string(step));
    const Frame frame = randomFrame(reference.scene(), rng, step, added);
    const SceneSession::Applied applied = session.apply(frame);
    const SceneSnapshot& s = *applied.snapshot;
    // The session casts afresh the changed trees that are mostly dead slots; so does the reference.
    reference.compactTrees(reference.apply(frame).changedReceivers);
    const MeshSelection delta = s.select(s.version - 1);
    for (const PartKey& key : delta.removedParts) held.erase(key);
    for (size_t i : delta.parts) {
      held[s.parts[i].key] = contentOf(*s.parts[i].mesh);
      if (!applied.result.radianceChanged) floorSent += s.parts[i].key.receiver.object == "floor";
    }
    // Values only: the held part keeps its shape and takes the new irradiance.
    for (size_t i : delta.valueParts) {
      ASSERT_TRUE(held.count(s.parts[i].key));
      auto& irradiance = std::get<1>(held.at(s.parts[i].key));
      ASSERT_EQ(irradiance.size(), s.parts[i].mesh->irradiance.size());
      irradiance = s.parts[i].mesh->irradiance;
      ++valueParts;
    }
    if (!applied.result.radianceChanged)
      for (const MeshPart& part : s.parts) floorHeld += part.key.receiver.object == "floor";

    reference.forgetMeshMemo();
    std::map<PartKey, Content> want;
    for (const Engine::ReceiverChunks& r : reference.meshChunks(reference.receiverFaces()))
      for (const Engine::MeshChunk& chunk : r.chunks)
        want[{{reference.scene().object(r.face.object).id, r.face.face}, chunk.key.x, chunk.key.y}] =
            contentOf(*chunk.mesh);
    ASSERT_EQ(held.size(), want.size());
    for (const auto& [key, content] : want) {
      ASSERT_TRUE(held.count(key)) << key.receiver.object << "/" << key.receiver.face << " " << key.x << "," << key.y;
      EXPECT_TRUE(held.at(key) == content) << key.receiver.object << "/" << key.receiver.face;
    }
    if (HasFailure()) return;
  }
  EXPECT_GT(floorHeld, 6u * 4);         // the floor is several chunks
  EXPECT_LT(floorSent * 2, floorHeld);  // of which a drag's frame sends a few
  EXPECT_GT(valueParts, 0u);            // radiance changes were sent as values
}

// A part's vertices' irradiance as floats, r, g, b each, of the receivers in mesh JSON, by
// "object/face": the exact values the binary mesh stands for.
std::map<std::string, std::vector<float>> jsonIrradiance(const json& mesh) {
  std::map<std::string, std::vector<float>> out;
  for (const json& r : mesh["receivers"]) {
    std::vector<float>& e = out[r["object"].get<std::string>() + "/" + std::to_string(r["face"].get<int>())];
    for (const json& v : r["irradiance"])
      for (int c = 0; c < 3; ++c) e.push_back(float(v[c].get<double>()));
  }
  return out;
}

// A light's radiance or colour changes every vertex's value and nothing of the triangulation:
// the binary delta has no geometry (no whole part, no vertex, no triangle), a part's irradiance
// alone, and under one light, white or coloured, one channel per vertex with the light's colour
// as the tint: at most a quarter of the whole mesh's bytes. Applied to the whole mesh it gives
// the new version's whole mesh bit for bit, whose every part is one channel with that tint too,
// and decodes within 2 f32 ulps of the JSON mesh's exact values. The JSON delta's receivers are
// values only too.
TEST(MeshDelta, ARadianceEditSendsValuesNotGeometry) {
  ModelSceneOptions options;
  options.kind = ModelKind::Teapot;
  options.triangles = 1000;
  const Scene scene = makeModelScene(options);
  SceneSession session("t", "teapot", scene);
  BinaryMesh held = parseBinary(
      mesh_binary::encode(*session.snapshot(), session.snapshot()->select(std::nullopt)));
  const Light light = scene.lights().at(0);
  ASSERT_TRUE(light.radiance.x == light.radiance.y &&
              light.radiance.y == light.radiance.z);  // white
  const std::vector<Vec3> radiances = {light.radiance * 1.3, Vec3(0.9, 1.1, 0.7) * light.radiance,
                                       Vec3(12, 10, 8), light.radiance * 0.6};
  for (size_t step = 0; step < radiances.size(); ++step) {
    const Vec3 radiance = radiances[step];
    SCOPED_TRACE("step " + std::to_string(step));
    Edit edit;
    edit.op = Edit::Op::SetLight;
    edit.id = light.id;
    edit.radiance = radiance;
    const SceneSession::Applied applied = session.apply(Frame{{edit}});
    EXPECT_TRUE(applied.result.radianceChanged);
    const SceneSnapshot& s = *applied.snapshot;
    const std::string whole = mesh_binary::encode(s, s.select(std::nullopt));
    const std::string deltaBytes = mesh_binary::encode(s, s.select(s.version - 1));
    const BinaryMesh delta = parseBinary(deltaBytes);
    EXPECT_EQ(delta.layout, mesh_binary::kLayoutVersion);
    EXPECT_TRUE(delta.parts.empty());
    EXPECT_TRUE(delta.removed.empty());
    EXPECT_EQ(delta.totalVertices, 0u);
    EXPECT_EQ(delta.totalTriangles, 0u);
    EXPECT_GT(delta.valueParts.size(), s.parts.size() / 2);
    EXPECT_LE(deltaBytes.size() * 4, whole.size()) << deltaBytes.size() << " of " << whole.size();
    // The light's colour over its largest channel ((1, 1, 1) when white); a part no light
    // reaches (all zero) is tinted (1, 1, 1).
    const double peak = std::max({radiance.x, radiance.y, radiance.z});
    const std::array<float, 3> tint = {float(radiance.x / peak), float(radiance.y / peak),
                                       float(radiance.z / peak)};
    auto expectTint = [&](uint32_t channels, const float (&got)[3], const std::vector<float>& e) {
      EXPECT_EQ(channels, 1u);
      const bool dark = std::all_of(e.begin(), e.end(), [](float x) { return x == 0.0f; });
      for (int c = 0; c < 3; ++c) EXPECT_EQ(got[c], dark ? 1.0f : tint[c]) << c;
    };
    for (const BinaryMesh::ValuePart& v : delta.valueParts) expectTint(v.channels, v.tint, v.irradiance);
    // Applied by (object, face, chunk), the held parts become the whole mesh.
    for (const BinaryMesh::ValuePart& v : delta.valueParts) {
      size_t matched = 0;
      for (BinaryMesh::Part& p : held.parts)
        if (held.objects.at(p.object) == delta.objects.at(v.object) && p.face == v.face &&
            p.x == v.x && p.y == v.y) {
          ASSERT_EQ(p.vertices, v.vertices);
          p.irradiance = v.irradiance;
          p.version = v.version;
          ++matched;
        }
      EXPECT_EQ(matched, 1u);
    }
    const BinaryMesh want = parseBinary(whole);
    ASSERT_EQ(held.parts.size(), want.parts.size());
    for (size_t p = 0; p < want.parts.size(); ++p) {
      EXPECT_EQ(held.parts[p].irradiance, want.parts[p].irradiance) << p;
      EXPECT_EQ(held.parts[p].positions, want.parts[p].positions) << p;
      EXPECT_EQ(held.parts[p].version, want.parts[p].version) << p;
      expectTint(want.parts[p].channels, want.parts[p].tint, want.parts[p].irradiance);
    }
    // A receiver is its parts one after the other: within 2 ulps of the JSON mesh's values.
    std::map<std::string, std::vector<float>> decoded;
    for (const BinaryMesh::Part& p : held.parts) {
      std::vector<float>& e = decoded[held.objects.at(p.object) + "/" + std::to_string(p.face)];
      e.insert(e.end(), p.irradiance.begin(), p.irradiance.end());
    }
    const auto truth = jsonIrradiance(meshJson(s, s.select(std::nullopt)));
    ASSERT_EQ(decoded.size(), truth.size());
    size_t inexact = 0;
    for (const auto& [key, e] : truth) {
      ASSERT_EQ(decoded[key].size(), e.size()) << key;
      for (size_t k = 0; k < e.size(); ++k) {
        EXPECT_TRUE(test::withinTwoUlps(decoded[key][k], e[k])) << key << " " << k << ": " << decoded[key][k] << " for " << e[k];
        inexact += decoded[key][k] != e[k];
      }
    }
    if (radiance.x == radiance.y && radiance.y == radiance.z) {
      EXPECT_EQ(inexact, 0u);  // grey: exact
    }

    const json jsonDelta = meshJson(s, s.select(s.version - 1));
    EXPECT_EQ(jsonDelta["version"], 2);
    EXPECT_FALSE(jsonDelta["receivers"].empty());
    for (const json& r : jsonDelta["receivers"])
      EXPECT_FALSE(r.contains("positions") || r.contains("triangles"));
    if (HasFailure()) return;
  }
}

TEST(MeshDelta, AcceptEncodingParsing) {
  EXPECT_TRUE(acceptsGzip("gzip"));
  EXPECT_TRUE(acceptsGzip("gzip, deflate, br"));
  EXPECT_TRUE(acceptsGzip("br;q=1.0, GZIP;q=0.5"));
  EXPECT_TRUE(acceptsGzip("*"));
  EXPECT_TRUE(acceptsGzip("x-gzip"));
  EXPECT_FALSE(acceptsGzip(""));
  EXPECT_FALSE(acceptsGzip("identity"));
  EXPECT_FALSE(acceptsGzip("deflate, br"));
  EXPECT_FALSE(acceptsGzip("gzip;q=0"));
  EXPECT_FALSE(acceptsGzip("gzip;q=0.000, *"));
  EXPECT_FALSE(acceptsGzip("gzipx"));
}


TEST(MeshDelta, BinaryMeshIsGzippedWhenTheClientAcceptsIt) {
  ServerOptions options = test::RunningServer::loopback();
  options.meshCompression = ServerOptions::MeshCompression::Always;
  test::RunningServer running(options);
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  client.set_decompress(false);  // see the bytes on the wire
  const std::string path = "/api/scenes/" + id + "/mesh?format=bin";
  const auto plain = client.Get(path.c_str(), {{"Accept-Encoding", "identity"}});
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 200);
  EXPECT_FALSE(plain->has_header("Content-Encoding"));
  EXPECT_EQ(plain->body.substr(0, 4), "PNMB");
  EXPECT_EQ(plain->get_header_value("X-Penumbra-Uncompressed-Bytes"), std::to_string(plain->body.size()));

  const auto packed = client.Get(path.c_str(), {{"Accept-Encoding", "gzip, deflate, br"}});
  ASSERT_TRUE(packed);
  ASSERT_EQ(packed->status, 200);
  EXPECT_EQ(packed->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(packed->get_header_value("Vary"), "Accept-Encoding");
  EXPECT_EQ(packed->get_header_value("X-Penumbra-Uncompressed-Bytes"), std::to_string(plain->body.size()));
  EXPECT_LT(packed->body.size(), plain->body.size() * 3 / 4);
  EXPECT_EQ(test::gunzip(packed->body), plain->body);

  // A client that decodes (httplib's, a browser's fetch) reads the same bytes.
  auto decoding = running.client();
  const auto decoded = decoding.Get(path.c_str(), {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(decoded);
  EXPECT_EQ(decoded->body, plain->body);
}

// Mesh JSON is written to the socket as it is made (chunked, never a document in memory): the
// same text plain or gzipped, a valid mesh, and a client leaving mid-answer harms nothing.
TEST(MeshDelta, MeshJsonIsStreamedInChunks) {
  test::RunningServer running;
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  client.set_decompress(false);
  const std::string path = "/api/scenes/" + id + "/mesh";
  const auto plain = client.Get(path.c_str(), {{"Accept-Encoding", "identity"}});
  ASSERT_TRUE(plain);
  ASSERT_EQ(plain->status, 200);
  EXPECT_EQ(plain->get_header_value("Transfer-Encoding"), "chunked");
  EXPECT_FALSE(plain->has_header("Content-Length"));
  EXPECT_EQ(plain->get_header_value("Cache-Control"), "no-store");
  EXPECT_EQ(plain->get_header_value("X-Penumbra-Version"), "0");
  ASSERT_GT(plain->body.size(), size_t(1) << 17);  // more than two of the writer's blocks
  EXPECT_EQ(plain->body.back(), '\n');
  const json mesh = json::parse(plain->body);
  EXPECT_EQ(mesh["format"], "penumbra.mesh");
  EXPECT_EQ(mesh["id"], id);
  EXPECT_GT(mesh["receivers"].size(), 0u);

  const auto packed = client.Get(path.c_str(), {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(packed);
  EXPECT_EQ(packed->get_header_value("Content-Encoding"), "gzip");
  EXPECT_EQ(test::gunzip(packed->body), plain->body);

  // Clients that read a little and close: the writer stops, the server serves on.
  for (int attempt = 0; attempt < 5; ++attempt) {
    test::TestClient leaving("127.0.0.1", running.port());
    size_t seen = 0;
    const auto cut = leaving.Get(path.c_str(), [&](const char*, size_t length) {
      seen += length;
      return seen < 1000;  // false: close the connection
    });
    EXPECT_FALSE(cut);
  }
  const auto again = client.Get(path.c_str(), {{"Accept-Encoding", "identity"}});
  ASSERT_TRUE(again);
  EXPECT_EQ(again->body, plain->body);
}

}  // namespace
}  // namespace penumbra::server

namespace penumbra::server {
namespace {

TEST(MeshDelta, LoopbackClientsGetUncompressedBytesByDefault) {
  test::RunningServer running;  // MeshCompression::Auto
  const std::string id = running.addBundled("cubes15");
  auto client = running.client();
  client.set_decompress(false);
  const auto res = client.Get(("/api/scenes/" + id + "/mesh?format=bin").c_str(), {{"Accept-Encoding", "gzip"}});
  ASSERT_TRUE(res);
  ASSERT_EQ(res->status, 200);
  EXPECT_FALSE(res->has_header("Content-Encoding"));
  EXPECT_EQ(res->body.substr(0, 4), "PNMB");
}

}  // namespace
}  // namespace penumbra::server
