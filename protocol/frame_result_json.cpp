#include "protocol/frame_result_json.h"

namespace penumbra::protocol {

namespace {

nlohmann::json faceJson(const Scene& scene, FaceId face) {
  if (scene.indexOfHandle(face.object))
    return {{"object", scene.object(face.object).id}, {"face", face.face}};
  return {{"handle", face.object}, {"face", face.face}};
}

}  // namespace

nlohmann::json frameResultCountsToJson(const FrameResult& result) {
  return {{"version", result.version},
          {"seconds",
           {{"remove", result.seconds.remove},
            {"add", result.seconds.add},
            {"relight", result.seconds.relight},
            {"total", result.seconds.total()}}},
          {"vertices",
           {{"relit", result.verticesRelit},
            {"changed", result.verticesChanged},
            {"created", result.verticesCreated}}},
          {"changed_receivers_count", result.changedReceivers.size()},
          {"removed_receivers_count", result.removedReceivers.size()},
          {"nodes_deleted", result.nodesDeleted},
          {"tree_rebuilds", result.treeRebuilds},
          {"full_rebuild", result.fullRebuild},
          {"radiance_changed", result.radianceChanged}};
}

nlohmann::json frameResultToJson(const FrameResult& result, const Scene& scene) {
  nlohmann::json changed = nlohmann::json::array(), removed = nlohmann::json::array();
  for (FaceId face : result.changedReceivers) changed.push_back(faceJson(scene, face));
  for (FaceId face : result.removedReceivers) removed.push_back(faceJson(scene, face));
  nlohmann::json out = frameResultCountsToJson(result);
  out["changed_receivers"] = std::move(changed);
  out["removed_receivers"] = std::move(removed);
  return out;
}

}  // namespace penumbra::protocol
