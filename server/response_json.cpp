#include "server/response_json.h"

#include "protocol/build_stats_json.h"

namespace penumbra::server {

using nlohmann::json;

json rebuildJson(const RebuildReport& r) {
  return {{"version", r.version},
          {"seconds",
           {{"build", r.buildSeconds},
            {"mesh", r.meshSeconds},
            {"total", r.buildSeconds + r.meshSeconds}}},
          {"mesh", {{"vertices", r.meshVertices}, {"triangles", r.meshTriangles}}},
          {"served_mesh", {{"vertices", r.servedVertices}, {"triangles", r.servedTriangles}}},
          {"stats", protocol::buildStatsToJson(r.stats)}};
}

json sceneSummaryJson(const SceneSnapshot& s) {
  return {{"id", s.id},
          {"name", s.name},
          {"version", s.version},
          {"objects", s.scene.objects().size()},
          {"faces", s.scene.faces().size()},
          {"receivers", s.receiverCount()},
          {"url", "/api/scenes/" + s.id}};
}

json changedAtJson(const SceneSnapshot& s, uint64_t after) {
  const MeshSelection selection = s.select(after);
  json changed = json::array(), removed = json::array();
  for (const ReceiverKey& key : selection.receivers) changed.push_back(toJson(key));
  for (const ReceiverKey& key : selection.removed) removed.push_back(toJson(key));
  return {{"version", s.version}, {"changed", std::move(changed)}, {"removed", std::move(removed)}};
}

nlohmann::json volumeInfoJson(const VolumeObject& volume) {
  const volume::ScalarVolume& data = *volume.data;
  nlohmann::json axes = nlohmann::json::array();
  for (int a = 0; a < 3; ++a) {
    const Vec3 edge = data.objectFromVoxel()[a] * double(data.size()[a] - 1);
    axes.push_back({edge.x, edge.y, edge.z});
  }
  return {{"id", volume.id},
          {"voxel_type", data.typeName()},
          {"size", {data.size().x, data.size().y, data.size().z}},
          {"value_range", {data.minValue(), data.maxValue()}},
          {"axes", std::move(axes)},
          {"isovalue", volume.isovalue}};
}

nlohmann::json volumesInfoJson(const Scene& scene) {
  nlohmann::json out = nlohmann::json::array();
  for (const VolumeObject& volume : scene.volumes()) out.push_back(volumeInfoJson(volume));
  return out;
}

}  // namespace penumbra::server
