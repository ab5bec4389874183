// Fuzz target: mesh `since` queries. One tiny-scene SceneSession per process is driven through
// a fixed history of frames (moves, a remove, an add back), every version's snapshot kept. Each
// input is up to 4 records of 9 bytes: a selector byte (which snapshot, how to read `since`) and 8
// bytes of `since`. For each: SceneSnapshot::select, then the delta property — the parts of
// version `since` with the delta applied are exactly the parts of the queried version — and
// mesh_binary::encode / meshJson of the selection (once per distinct query).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "fuzz_support.h"
#include "protocol/edits_json.h"
#include "server/mesh_binary.h"
#include "server/scene_session.h"

using namespace penumbra;
using penumbra::server::PartKey;
using penumbra::server::SceneSnapshot;

namespace {

const char* const kHistory[] = {
    R"({"edits":[{"op":"move","id":"box","transform":{"translate":[0.3,0.5,0],"rotate_deg":[0,30,0]}}]})",
    R"({"edits":[{"op":"move","id":"box","transform":{"translate":[0.6,0.5,0.1],"rotate_deg":[0,40,0]}}]})",
    R"({"edits":[{"op":"set_light","id":"lamp","radiance":[12,12,12]}]})",  // values only
    R"({"edits":[{"op":"remove","id":"box2"}]})",
    R"({"edits":[{"op":"set_light","id":"lamp","radiance":[12,10,8]}]})",  // values only, coloured
    R"({"edits":[{"op":"move","id":"box","transform":{"translate":[0.6,0.5,0.4],"rotate_deg":[0,45,0]}}]})",
    R"({"edits":[{"op":"add","object":{"id":"box2","material":"white",
       "transform":{"translate":[-1.5,0.25,0.5],"scale":[0.5,0.5,0.5]},
       "vertices":[[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],
                   [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],
       "faces":[[0,3,2,1],[4,5,6,7],[0,4,7,3],[1,2,6,5],[0,1,5,4],[3,7,6,2]]}}]})",
    R"({"edits":[{"op":"move","id":"box2","transform":{"translate":[-1.0,0.25,0.5],"scale":[0.5,0.5,0.5]}}]})",
};

// Every version's snapshot, index = version.
const std::vector<std::shared_ptr<const SceneSnapshot>>& history() {
  static const auto snapshots = [] {
    server::SceneSession session("s", "tiny", fuzz::tinyScene());
    std::vector<std::shared_ptr<const SceneSnapshot>> all{session.snapshot()};
    for (const char* frame : kHistory)
      all.push_back(session.apply(protocol::frameFromJson(nlohmann::json::parse(frame))).snapshot);
    return all;
  }();
  return snapshots;
}

bool sameMesh(const ReceiverMesh& a, const ReceiverMesh& b) {
  return a.positions == b.positions && a.irradiance == b.irradiance && a.classes == b.classes &&
         a.triangles == b.triangles;
}

using Parts = std::map<PartKey, std::shared_ptr<const ReceiverMesh>>;

Parts partsOf(const SceneSnapshot& s) {
  Parts parts;
  for (const auto& part : s.parts) parts[part.key] = part.mesh;
  return parts;
}

// The delta property and the encoders depend on (snapshot, since) alone, and the history has few
// such pairs: each is checked once per process, so the executions go to new selections (the
// encoders ran every time before, and kept this target at ~40 executions a second).
bool firstTime(const SceneSnapshot& snapshot, std::optional<uint64_t> since) {
  static std::set<std::pair<uint64_t, std::optional<uint64_t>>> seen;
  return seen.emplace(snapshot.version, since).second;
}

void checkQuery(const SceneSnapshot& snapshot, std::optional<uint64_t> since) {
  const server::MeshSelection selection = snapshot.select(since);
  for (size_t i = 1; i < selection.parts.size(); ++i)
    fuzz::check(selection.parts[i - 1] < selection.parts[i], "selected parts not ascending");
  for (size_t i : selection.parts) {
    fuzz::check(i < snapshot.parts.size(), "selected part out of range");
    fuzz::check(!since || snapshot.parts[i].version > *since, "selected part not newer than since");
  }
  for (size_t i : selection.valueParts) {
    fuzz::check(since && i < snapshot.parts.size(), "value part out of range or in a whole mesh");
    fuzz::check(snapshot.parts[i].version > *since && snapshot.parts[i].shapeVersion <= *since,
                "value part not newer than since, or reshaped after it");
  }
  if (since && *since >= snapshot.version)
    fuzz::check(selection.parts.empty() && selection.removedParts.empty(), "a delta from the future");
  // The route refuses since > version (400) before encoding: the binary header has 32 bits.
  if (since && *since > snapshot.version) return;
  if (!firstTime(snapshot, since)) return;
  if (since && *since < snapshot.version) {
    Parts rebuilt = partsOf(*history()[*since]);
    for (const PartKey& key : selection.removedParts) rebuilt.erase(key);
    for (size_t i : selection.parts) rebuilt[snapshot.parts[i].key] = snapshot.parts[i].mesh;
    for (size_t i : selection.valueParts) {  // the held shape, the new irradiance
      const auto held = rebuilt.find(snapshot.parts[i].key);
      fuzz::check(held != rebuilt.end(), "value part not held at `since`");
      auto mesh = std::make_shared<ReceiverMesh>(*held->second);
      mesh->irradiance = snapshot.parts[i].mesh->irradiance;
      held->second = std::move(mesh);
    }
    const Parts expected = partsOf(snapshot);
    fuzz::check(rebuilt.size() == expected.size(), "delta applied to `since` has other parts");
    for (const auto& [key, mesh] : expected)
      fuzz::check(rebuilt.count(key) && sameMesh(*rebuilt.at(key), *mesh), "delta applied to `since` differs");
  }
  const std::string binary = server::mesh_binary::encode(snapshot, selection);
  fuzz::check(binary.size() >= server::mesh_binary::kHeaderBytes &&
                  std::memcmp(binary.data(), server::mesh_binary::kMagic, 4) == 0,
              "binary mesh without its header");
  // JSON of deltas only: the whole mesh as JSON (the same writer over every part) cost ~50 ms an
  // input under the sanitizers and kept this target at 4 executions a second.
  if (since) {
    std::ostringstream text;
    snapshot.writeMeshJson(text, selection);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto& snapshots = history();
  for (size_t at = 0; at + 9 <= size && at < 9 * 4; at += 9) {  // at most 4 queries an input
    const uint8_t selector = data[at];
    uint64_t raw = 0;
    std::memcpy(&raw, data + at + 1, 8);
    const SceneSnapshot& snapshot = *snapshots[(selector >> 2) % snapshots.size()];
    std::optional<uint64_t> since;
    if (selector & 1) since = (selector & 2) ? raw : raw % (snapshots.size() + 2);
    checkQuery(snapshot, since);
  }
  return 0;
}
