#include "server/scene_snapshot.h"

#include <algorithm>
#include <map>
#include <ostream>
#include <set>

#include "protocol/mesh_json.h"

namespace penumbra::server {

nlohmann::json toJson(const ReceiverKey& key) {
  return {{"object", key.object}, {"face", key.face}};
}

nlohmann::json toJson(const PartKey& key) {
  return {{"object", key.receiver.object}, {"face", key.receiver.face}, {"chunk", {key.x, key.y}}};
}

namespace {

// Calls visit(receiver key, first part, end part) for each receiver's run of parts.
template <class Visit>
void forEachReceiver(const std::vector<MeshPart>& parts, Visit visit) {
  for (size_t begin = 0; begin < parts.size();) {
    size_t end = begin + 1;
    while (end < parts.size() && parts[end].key.receiver == parts[begin].key.receiver) ++end;
    visit(parts[begin].key.receiver, begin, end);
    begin = end;
  }
}

ReceiverMesh wholeReceiver(const std::vector<MeshPart>& parts, size_t begin, size_t end) {
  ReceiverMesh out;
  out.face = parts[begin].mesh->face;
  out.normal = parts[begin].mesh->normal;
  for (size_t i = begin; i < end; ++i) appendMesh(out, *parts[i].mesh);
  return out;
}

}  // namespace

MeshSelection SceneSnapshot::select(std::optional<uint64_t> since) const {
  MeshSelection selection;
  if (since && *since < removedFloor) since.reset();  // what left before is forgotten
  selection.since = since;
  std::set<ReceiverKey> lostPart;  // receivers with a part removed after `since`
  if (since)
    for (const auto& [key, removedAt] : removed)
      if (removedAt > *since) {
        selection.removedParts.push_back(key);
        lostPart.insert(key.receiver);
      }
  forEachReceiver(parts, [&](const ReceiverKey& key, size_t begin, size_t end) {
    bool reshaped = !since || lostPart.erase(key) > 0, changed = reshaped;
    for (size_t i = begin; i < end; ++i) {
      if (since && parts[i].version <= *since) continue;
      changed = true;
      if (since && parts[i].shapeVersion <= *since) {
        selection.valueParts.push_back(i);
      } else {
        selection.parts.push_back(i);
        reshaped = true;
      }
    }
    if (changed) selection.receivers.push_back(key);
    if (changed && !reshaped) selection.valueReceivers.push_back(key);
  });
  // What is left lost a part and has none now: the receiver has left.
  selection.removed.assign(lostPart.begin(), lostPart.end());
  return selection;
}

void SceneSnapshot::forgetRemovedUpTo(uint64_t floor) {
  if (floor <= removedFloor) return;
  removedFloor = floor;
  std::erase_if(removed, [&](const auto& entry) { return entry.second <= floor; });
}

const Mesh& SceneSnapshot::mesh() const {
  std::call_once(meshOnce_, [this] {
    forEachReceiver(parts, [&](const ReceiverKey&, size_t begin, size_t end) {
      mesh_.receivers.push_back(wholeReceiver(parts, begin, end));
    });
  });
  return mesh_;
}

size_t SceneSnapshot::receiverCount() const {
  size_t n = 0;
  forEachReceiver(parts, [&](const ReceiverKey&, size_t, size_t) { ++n; });
  return n;
}

size_t SceneSnapshot::vertexCount() const {
  size_t n = 0;
  for (const MeshPart& part : parts) n += part.mesh->positions.size();
  return n;
}

size_t SceneSnapshot::triangleCount() const {
  size_t n = 0;
  for (const MeshPart& part : parts) n += part.mesh->triangles.size();
  return n;
}

void SceneSnapshot::writeMeshJson(std::ostream& out, const MeshSelection& selection,
                                  const protocol::MeshJsonExtras& more) const {
  const std::set<ReceiverKey> wanted(selection.receivers.begin(), selection.receivers.end());
  const std::set<ReceiverKey> valuesOnly(selection.valueReceivers.begin(),
                                         selection.valueReceivers.end());
  const bool whole = !selection.since;  // every receiver: the cached whole mesh
  Mesh chosen;
  std::vector<uint64_t> versions;
  std::vector<bool> chosenValuesOnly;
  forEachReceiver(parts, [&](const ReceiverKey& key, size_t begin, size_t end) {
    if (!wanted.count(key)) return;
    chosenValuesOnly.push_back(valuesOnly.count(key) > 0);
    if (!whole) chosen.receivers.push_back(wholeReceiver(parts, begin, end));
    uint64_t newest = 0;
    for (size_t i = begin; i < end; ++i) newest = std::max(newest, parts[i].version);
    if (selection.since)  // a receiver that only lost a chunk changed at that version
      for (const auto& [removedKey, removedAt] : removed)
        if (removedKey.receiver == key) newest = std::max(newest, removedAt);
    versions.push_back(newest);
  });
  protocol::MeshJsonExtras extras;
  extras.root = more.root.is_object() ? more.root : nlohmann::json::object();
  // A delta is mesh delta JSON v2 (its receivers may be values only); a whole mesh is mesh JSON v1.
  if (selection.since) extras.root["version"] = kMeshDeltaJsonVersion;
  extras.root["id"] = id;
  extras.root["scene_version"] = version;
  extras.root["since"] = selection.since ? nlohmann::json(*selection.since) : nlohmann::json(nullptr);
  nlohmann::json removedJson = nlohmann::json::array();
  for (const ReceiverKey& key : selection.removed) removedJson.push_back(toJson(key));
  extras.root["removed"] = std::move(removedJson);
  extras.receiver = [&](size_t k) {
    nlohmann::json members = more.receiver ? more.receiver(k) : nlohmann::json::object();
    if (!members.is_object()) members = nlohmann::json::object();
    members["scene_version"] = versions.at(k);
    return members;
  };
  extras.valuesOnly = [&](size_t k) { return bool(chosenValuesOnly.at(k)); };
  protocol::writeMeshJson(out, scene, whole ? mesh() : chosen, name, extras);
}

}  // namespace penumbra::server
