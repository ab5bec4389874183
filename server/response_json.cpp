#include "server/response_json.h"


namespace penumbra::server {

using nlohmann::json;

json buildStatsJson(const BuildStats& s) {
  const BuildTimings& t = s.seconds;
  return {{"faces", s.faces},
          {"receivers", s.receivers},
          {"lights", s.lights},
          {"candidate_pairs", s.candidatePairs},
          {"pairs_with_shadow", s.pairsWithShadow},
          {"tree_nodes", s.treeNodes},
          {"cells", s.cells},
          {"vertices",
           {{"total", s.vertices},
            {"lit", s.litVertices},
            {"penumbra", s.penumbraVertices},
            {"umbra", s.umbraVertices}}},
          {"seconds",
           {{"ordering", t.ordering},
            {"cube", t.cube},
            {"casting_and_merging", t.castingAndMerging},
            {"illumination", t.illumination},
            {"triangulation", t.triangulation},
            {"total", t.total()}}}};
}

json rebuildJson(const RebuildReport& r) {
  return {{"version", r.version},
          {"seconds",
           {{"build", r.buildSeconds},
            {"mesh", r.meshSeconds},
            {"total", r.buildSeconds + r.meshSeconds}}},
          {"mesh", {{"vertices", r.meshVertices}, {"triangles", r.meshTriangles}}},
          {"served_mesh", {{"vertices", r.servedVertices}, {"triangles", r.servedTriangles}}},
          {"stats", buildStatsJson(r.stats)}};
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
