#include "server/scene_session.h"

#include <map>
#include <set>

namespace penumbra::server {

namespace {

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::vector<ReceiverKey> receiverKeysOf(const Scene& scene, const Mesh& mesh) {
  std::vector<ReceiverKey> keys;
  keys.reserve(mesh.receivers.size());
  for (const ReceiverMesh& r : mesh.receivers)
    keys.push_back({scene.object(r.face.object).id, r.face.face});
  return keys;
}

bool sameMesh(const ReceiverMesh& a, const ReceiverMesh& b) {
  return a.normal == b.normal && a.positions == b.positions && a.irradiance == b.irradiance &&
         a.classes == b.classes && a.triangles == b.triangles;
}

}  // namespace

SceneSession::SceneSession(std::string id, std::string name, Scene scene, EngineSettings settings)
    : id_(std::move(id)), settings_(settings) {
  engine_ = std::make_unique<Engine>(std::move(scene), settings_);
  auto first = std::make_shared<SceneSnapshot>();
  first->id = id_;
  first->name = std::move(name);
  first->version = engine_->version();
  first->mesh = engine_->mesh();
  first->buildStats = engine_->stats();
  first->scene = engine_->scene();
  first->receiverKeys = receiverKeysOf(first->scene, first->mesh);
  first->receiverVersions.assign(first->mesh.receivers.size(), first->version);
  current_ = std::move(first);
}

std::shared_ptr<const SceneSnapshot> SceneSession::snapshot() const {
  std::lock_guard lock(publishMutex_);
  return current_;
}

SceneSession::Applied SceneSession::apply(const Frame& frame) {
  std::lock_guard edit(editMutex_);
  const std::shared_ptr<const SceneSnapshot> previous = snapshot();
  FrameResult result = engine_->apply(frame);  // throws EditError before changing anything

  // Build the next whole version beside the published one, then swap it in.
  auto next = std::make_shared<SceneSnapshot>();
  next->id = previous->id;
  next->name = previous->name;
  next->version = result.version;
  next->buildStats = previous->buildStats;
  next->scene = engine_->scene();

  // Only the receivers the frame changed (and new ones) are meshed again; the others
  // keep the previous version's mesh, which is what a fresh mesh() would give them.
  const auto meshStart = std::chrono::steady_clock::now();
  std::map<FaceId, size_t> previousByFace;
  for (size_t i = 0; i < previous->mesh.receivers.size(); ++i)
    previousByFace.emplace(previous->mesh.receivers[i].face, i);
  const std::set<FaceId> changed(result.changedReceivers.begin(), result.changedReceivers.end());
  std::vector<FaceId> remesh;
  for (const Engine::Receiver& r : engine_->receivers())
    if (changed.count(r.face) || !previousByFace.count(r.face)) remesh.push_back(r.face);
  Mesh remeshed = engine_->mesh(remesh);
  const Engine::MeshCacheCounters cells = engine_->lastMeshCounters();
  next->mesh.receivers.reserve(engine_->receivers().size());
  size_t fresh = 0;
  for (const Engine::Receiver& r : engine_->receivers()) {
    if (fresh < remeshed.receivers.size() && remeshed.receivers[fresh].face == r.face)
      next->mesh.receivers.push_back(std::move(remeshed.receivers[fresh++]));
    else
      next->mesh.receivers.push_back(previous->mesh.receivers[previousByFace.at(r.face)]);
  }
  const double meshSeconds = secondsSince(meshStart);
  next->receiverKeys = receiverKeysOf(next->scene, next->mesh);

  // A receiver's version moves only when its mesh data really changed, so `since`
  // deltas carry what a client must redraw, whatever the engine recomputed.
  std::map<ReceiverKey, size_t> before;
  for (size_t i = 0; i < previous->receiverKeys.size(); ++i)
    before.emplace(previous->receiverKeys[i], i);
  next->receiverVersions.resize(next->mesh.receivers.size());
  for (size_t i = 0; i < next->receiverKeys.size(); ++i) {
    const auto it = before.find(next->receiverKeys[i]);
    const bool unchanged = it != before.end() &&
                           sameMesh(previous->mesh.receivers[it->second], next->mesh.receivers[i]);
    next->receiverVersions[i] = unchanged ? previous->receiverVersions[it->second] : next->version;
    if (it != before.end()) before.erase(it);
  }
  // What is left in `before` has left the scene; a key that came back is live again.
  const std::set<ReceiverKey> live(next->receiverKeys.begin(), next->receiverKeys.end());
  for (const auto& [key, removedAt] : previous->removed)
    if (!live.count(key)) next->removed.emplace_back(key, removedAt);
  for (const auto& [key, index] : before) next->removed.emplace_back(key, next->version);

  next->lastFrame = result;
  std::shared_ptr<const SceneSnapshot> published = std::move(next);
  publish(published);
  return {std::move(result), std::move(published), meshSeconds, remesh.size(), cells};
}

void SceneSession::publish(std::shared_ptr<const SceneSnapshot> next) {
  {
    std::lock_guard lock(publishMutex_);
    current_ = std::move(next);
  }
  published_.notify_all();
}

RebuildReport SceneSession::rebuild() {
  std::lock_guard lock(rebuildMutex_);
  const std::shared_ptr<const SceneSnapshot> served = snapshot();
  RebuildReport report;
  report.version = served->version;
  const auto start = std::chrono::steady_clock::now();
  Engine fresh(served->scene, settings_);
  report.buildSeconds = secondsSince(start);
  const auto meshStart = std::chrono::steady_clock::now();
  const Mesh mesh = fresh.mesh();
  report.meshSeconds = secondsSince(meshStart);
  report.stats = fresh.stats();
  report.meshVertices = mesh.vertexCount();
  report.meshTriangles = mesh.triangleCount();
  report.servedVertices = served->mesh.vertexCount();
  report.servedTriangles = served->mesh.triangleCount();
  {
    std::lock_guard published(publishMutex_);
    lastRebuild_ = report;
  }
  return report;
}

std::optional<RebuildReport> SceneSession::lastRebuild() const {
  std::lock_guard lock(publishMutex_);
  return lastRebuild_;
}

std::shared_ptr<const SceneSnapshot> SceneSession::waitForVersionAfter(
    uint64_t after, std::chrono::milliseconds timeout) const {
  std::unique_lock lock(publishMutex_);
  published_.wait_for(lock, timeout, [&] { return closed_ || current_->version > after; });
  return current_;
}

void SceneSession::close() {
  {
    std::lock_guard lock(publishMutex_);
    closed_ = true;
  }
  published_.notify_all();
}

bool SceneSession::closed() const {
  std::lock_guard lock(publishMutex_);
  return closed_;
}

}  // namespace penumbra::server
