#include "server/scene_snapshot.h"

#include "protocol/mesh_json.h"

namespace penumbra::server {

nlohmann::json toJson(const ReceiverKey& key) {
  return {{"object", key.object}, {"face", key.face}};
}

MeshSelection SceneSnapshot::select(std::optional<uint64_t> since) const {
  MeshSelection selection;
  selection.since = since;
  for (size_t i = 0; i < mesh.receivers.size(); ++i)
    if (!since || receiverVersions[i] > *since) selection.receivers.push_back(i);
  if (since)
    for (const auto& [key, removedAt] : removed)
      if (removedAt > *since) selection.removed.push_back(key);
  return selection;
}

nlohmann::json SceneSnapshot::meshJson(const MeshSelection& selection) const {
  nlohmann::json root;
  if (selection.receivers.size() == mesh.receivers.size()) {
    root = protocol::meshToJson(scene, mesh, name);
  } else {
    Mesh part;
    part.receivers.reserve(selection.receivers.size());
    for (size_t i : selection.receivers) part.receivers.push_back(mesh.receivers[i]);
    root = protocol::meshToJson(scene, part, name);
  }
  nlohmann::json& receivers = root["receivers"];
  for (size_t k = 0; k < selection.receivers.size(); ++k)
    receivers[k]["scene_version"] = receiverVersions[selection.receivers[k]];
  root["id"] = id;
  root["scene_version"] = version;
  root["since"] = selection.since ? nlohmann::json(*selection.since) : nlohmann::json(nullptr);
  nlohmann::json removedJson = nlohmann::json::array();
  for (const ReceiverKey& key : selection.removed) removedJson.push_back(toJson(key));
  root["removed"] = std::move(removedJson);
  return root;
}

}  // namespace penumbra::server
