#include "core/engine/engine.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "core/geom/clip.h"
#include "core/illum/face_lookup.h"
#include "core/illum/light_sum.h"
#include "core/shadow/cast_shadow.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Polygon2 polygonInFrame(const Polygon3& polygon, const PlaneFrame& frame) {
  Polygon2 out;
  out.reserve(polygon.size());
  for (const Vec3& p : polygon) out.push_back(frame.to2D(p));
  return out;
}

// Where light `light`'s plane cuts the receiver: the part behind it, as an umbra of
// the pseudo-occluder kLightPlaneOccluder, so no triangle straddles the line where
// the irradiance falls to zero.
std::optional<SingleShadow> lightPlaneShadow(const Scene& scene, size_t light, const Face& receiver,
                                             const PlaneFrame& frame) {
  const Plane lightPlane = scene.lights()[light].plane();
  const double eps = scene.tolerance().length();
  const Split3 split = splitByPlane(receiver.polygon, lightPlane, eps);
  if (split.front.empty() || split.back.empty()) return std::nullopt;
  SingleShadow shadow;
  shadow.light = uint32_t(light);
  shadow.occluder = kLightPlaneOccluder;
  shadow.receiver = receiver.id;
  shadow.penumbra = polygonInFrame(split.back, frame);
  shadow.umbra = shadow.penumbra;
  // The chord along the light's plane: the back part's vertices on the plane.
  std::vector<Vec2> chord;
  for (const Vec3& p : split.back)
    if (std::abs(lightPlane.signedDistance(p)) <= eps) chord.push_back(frame.to2D(p));
  if (chord.size() != 2) return std::nullopt;
  CriticalSegment segment;
  segment.a = chord[0];
  segment.b = chord[1];
  segment.kind = SegmentKind::Umbra;
  shadow.segments.push_back(segment);
  return shadow;
}

}  // namespace

Engine::Engine(Scene scene, EngineSettings settings, const EngineProgress& progress)
    : scene_(std::move(scene)), settings_(settings) {
  if (meshSpacing() > 0 && settings_.meshChunkSquares > 0) {
    meshChunkSquares_ = settings_.meshChunkSquares;
  } else if (meshSpacing() > 0 && settings_.meshChunkSquares == 0) {
    // Cells grow with the faces per lattice square (150 cubes: ~1 face a square and
    // ~40 cells; 1500 cubes: ~9 and ~700): denser scenes get smaller chunks.
    const double squares = EngineSettings::kDefaultSpacingDivisions * EngineSettings::kDefaultSpacingDivisions;
    const double facesPerSquare = double(scene_.faces().size()) / squares;
    meshChunkSquares_ = facesPerSquare <= 1.5 ? 4 : facesPerSquare <= 6 ? 2 : 1;
  }
  build(progress);
}

const Engine::Receiver* Engine::receiver(FaceId face) const {
  const auto it = receiverIndex_.find(face);
  return it == receiverIndex_.end() ? nullptr : &receivers_[it->second];
}

const std::set<FaceId>& Engine::castOn(FaceId occluder) const {
  static const std::set<FaceId> kNone;
  const auto it = castOn_.find(occluder);
  return it == castOn_.end() ? kNone : it->second;
}

void Engine::build(const EngineProgress& progress) {
  const size_t lightCount = scene_.lights().size();
  stats_ = BuildStats{};
  stats_.faces = scene_.faces().size();
  stats_.lights = lightCount;

  // Front-to-back orders (§2.1).
  auto start = Clock::now();
  for (size_t l = 0; l < lightCount; ++l) {
    orders_.push_back(std::make_unique<FaceOrder>(scene_, l));
    stats_.orderFragments += orders_.back()->counters().fragments;
  }
  stats_.seconds.ordering = secondsSince(start);

  // Shadow overlap cubes (§2.2).
  start = Clock::now();
  OverlapCubeSettings cubeSettings;
  cubeSettings.grid = settings_.overlapGrid;
  for (size_t l = 0; l < lightCount; ++l) {
    cubes_.push_back(std::make_unique<OverlapCube>(scene_, l, cubeSettings));
    stats_.tiles += cubes_.back()->tileCount();
  }
  stats_.seconds.cube = secondsSince(start);

  // One DM-tree per receiving face.
  start = Clock::now();
  const auto& faces = scene_.faces();
  std::map<FaceId, const Face*> faceById;
  for (const Face& face : faces) {
    faceById[face.id] = &face;
    if (!scene_.receivesLight(face)) continue;
    receiverIndex_[face.id] = receivers_.size();
    receivers_.push_back(makeReceiver(face));
  }
  stats_.receivers = receivers_.size();

  // Cast every candidate pair both ways (§2.3), occluders in front-to-back order.
  for (size_t l = 0; l < lightCount; ++l) {
    const auto pairs = cubes_[l]->candidatePairs();
    stats_.candidatePairs += pairs.size();
    struct Attempt {
      size_t occluderRank, receiverRank;
      FaceId occluder, receiver;
    };
    std::vector<Attempt> attempts;
    const FaceOrder& order = *orders_[l];
    for (const auto& [a, b] : pairs) {
      if (!order.contains(a) || !order.contains(b)) continue;
      attempts.push_back({order.rank(a), order.rank(b), a, b});
      attempts.push_back({order.rank(b), order.rank(a), b, a});
    }
    std::sort(attempts.begin(), attempts.end(), [](const Attempt& x, const Attempt& y) {
      return std::tie(x.occluderRank, x.receiverRank) < std::tie(y.occluderRank, y.receiverRank);
    });
    for (size_t i = 0; i < attempts.size(); ++i) {
      const Attempt& attempt = attempts[i];
      if (progress && i % 4096 == 0) progress("casting", i, attempts.size());
      const auto found = receiverIndex_.find(attempt.receiver);
      if (found == receiverIndex_.end()) continue;
      Receiver& receiver = receivers_[found->second];
      ++stats_.castAttempts;
      if (castPair(l, *faceById.at(attempt.occluder), receiver)) ++stats_.pairsWithShadow;
    }
    if (progress) progress("casting", attempts.size(), attempts.size());
  }
  stats_.seconds.castingAndMerging = secondsSince(start);

  // Illuminate every vertex (§2.4).
  start = Clock::now();
  for (size_t r = 0; r < receivers_.size(); ++r) {
    if (progress) progress("illumination", r, receivers_.size());
    illuminate(receivers_[r]);
  }
  if (progress) progress("illumination", receivers_.size(), receivers_.size());
  stats_.seconds.illumination = secondsSince(start);

  for (const Receiver& receiver : receivers_) {
    stats_.treeNodes += receiver.tree.internalNodeCount();
    stats_.cells += receiver.tree.cellCount();
    for (VertexId v : receiver.tree.vertices()) {
      const VertexIrradiance& value = receiver.values[v.index];
      ++stats_.vertices;
      stats_.comparisons += value.comparisons;
      switch (value.lightClass) {
        case LightClass::Lit: ++stats_.litVertices; break;
        case LightClass::Penumbra: ++stats_.penumbraVertices; break;
        case LightClass::Umbra: ++stats_.umbraVertices; break;
      }
    }
  }
}

Engine::Receiver Engine::makeReceiver(const Face& face) const {
  const PlaneFrame frame = PlaneFrame::onPlane(face.plane, face.polygon[0]);
  Receiver receiver{face.id, frame, DmTree(polygonInFrame(face.polygon, frame), scene_.tolerance()), {}, {}, {}};
  for (size_t l = 0; l < scene_.lights().size(); ++l)
    if (const auto horizon = lightPlaneShadow(scene_, l, face, frame)) receiver.tree.insert(*horizon);
  return receiver;
}

std::optional<InsertResult> Engine::castPair(size_t light, const Face& occluder, Receiver& receiver) {
  const Face* face = findFace(scene_, receiver.face);
  if (!face) throw std::logic_error("Engine: receiver without a scene face");
  const auto shadow = castShadow(scene_, light, occluder, *face, receiver.frame);
  if (!shadow) return std::nullopt;
  InsertResult inserted = receiver.tree.insert(*shadow);
  castOn_[occluder.id].insert(receiver.face);
  castBy_[receiver.face].insert(occluder.id);
  return inserted;
}

void Engine::castAllOn(Receiver& receiver) {
  const Face* face = findFace(scene_, receiver.face);
  if (!face) throw std::logic_error("Engine: receiver without a scene face");
  for (size_t l = 0; l < scene_.lights().size(); ++l) {
    const FaceOrder& order = *orders_[l];
    if (!order.contains(receiver.face)) continue;
    std::vector<std::pair<size_t, FaceId>> occluders;
    for (FaceId candidate : cubes_[l]->candidates(receiver.face))
      if (order.contains(candidate)) occluders.push_back({order.rank(candidate), candidate});
    std::sort(occluders.begin(), occluders.end());
    for (const auto& [rank, occluder] : occluders) castPair(l, *findFace(scene_, occluder), receiver);
  }
}

void Engine::forgetReceived(FaceId face) {
  const auto it = castBy_.find(face);
  if (it == castBy_.end()) return;
  for (FaceId occluder : it->second) {
    const auto on = castOn_.find(occluder);
    if (on == castOn_.end()) continue;
    on->second.erase(face);
    if (on->second.empty()) castOn_.erase(on);
  }
  castBy_.erase(it);
}

void Engine::growSlots(Receiver& receiver) {
  const size_t slots = receiver.tree.mesh().vertexSlots();
  if (receiver.values.size() >= slots) return;
  receiver.values.resize(slots);
  receiver.perLight.resize(slots);
  receiver.litAt.resize(slots, Vec2(std::numeric_limits<double>::quiet_NaN()));
}

void Engine::illuminate(Receiver& receiver) {
  const size_t slots = receiver.tree.mesh().vertexSlots();
  // Headroom: a big receiver's first edits then grow its arrays in place instead of
  // moving every value (untouched capacity costs no memory until used).
  const size_t capacity = slots + slots / 4 + 64;
  receiver.values.reserve(capacity);
  receiver.perLight.reserve(capacity);
  receiver.litAt.reserve(capacity);
  receiver.values.assign(slots, VertexIrradiance{});
  receiver.perLight.assign(slots, {});
  receiver.litAt.assign(slots, Vec2(std::numeric_limits<double>::quiet_NaN()));
  for (VertexId v : receiver.tree.vertices()) relightVertex(receiver, v);
}

void Engine::relightVertex(Receiver& receiver, VertexId v) const {
  const DmTree& tree = receiver.tree;
  std::vector<const OccluderList*> lists;
  const std::vector<CellId> around = tree.cellsAround(v);
  for (CellId c : around) lists.push_back(&tree.occluders(c));
  const Vec3 p = receiver.frame.to3D(tree.position(v));
  auto& perLight = receiver.perLight[v.index];
  perLight.clear();
  for (size_t l = 0; l < scene_.lights().size(); ++l)
    perLight.push_back(illuminateVertex(scene_, l, p, receiver.frame.normal, lists));
  receiver.values[v.index] = sumLights(scene_, perLight);
  receiver.litAt[v.index] = tree.position(v);
  for (CellId c : around) receiver.tree.touch(c);  // their corner values may have changed
}

void Engine::compactReceivers(const std::vector<bool>& dropped) {
  std::vector<Receiver> kept;
  kept.reserve(receivers_.size());
  for (size_t i = 0; i < receivers_.size(); ++i)
    if (!dropped[i]) kept.push_back(std::move(receivers_[i]));
  std::stable_sort(kept.begin(), kept.end(), [](const Receiver& a, const Receiver& b) { return a.face < b.face; });
  receivers_ = std::move(kept);
  receiverIndex_.clear();
  for (size_t i = 0; i < receivers_.size(); ++i) receiverIndex_[receivers_[i].face] = i;
}

bool Engine::insideEditVolume(const Face& face) const {
  const double eps = scene_.tolerance().length();
  for (const auto& cube : cubes_)
    for (const Vec3& v : face.polygon) {
      const Vec3 rel = v - cube->cubeMin();
      if (glm::any(glm::lessThan(rel, Vec3(-eps))) || glm::any(glm::greaterThan(rel, Vec3(cube->cubeSide() + eps))))
        return false;
    }
  return true;
}

void Engine::pruneMeshMemo() {
  for (auto it = meshMemo_.begin(); it != meshMemo_.end();)
    it = receiverIndex_.count(it->first) ? std::next(it) : meshMemo_.erase(it);
}

Mesh Engine::mesh() {
  const auto start = Clock::now();
  meshCounters_ = {};
  Mesh out;
  out.receivers.reserve(receivers_.size());
  for (const Receiver& receiver : receivers_) out.receivers.push_back(meshReceiver(receiver));
  pruneMeshMemo();
  stats_.seconds.triangulation = secondsSince(start);
  return out;
}

std::vector<size_t> Engine::receiverIndices(const std::vector<FaceId>& only) const {
  std::vector<size_t> indices;
  for (FaceId face : only)
    if (const auto it = receiverIndex_.find(face); it != receiverIndex_.end()) indices.push_back(it->second);
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  return indices;
}

Mesh Engine::mesh(const std::vector<FaceId>& only) {
  meshCounters_ = {};
  const std::vector<size_t> indices = receiverIndices(only);
  Mesh out;
  out.receivers.reserve(indices.size());
  for (size_t i : indices) out.receivers.push_back(meshReceiver(receivers_[i]));
  pruneMeshMemo();
  return out;
}

std::vector<Engine::ReceiverChunks> Engine::meshChunks(const std::vector<FaceId>& only) {
  meshCounters_ = {};
  std::vector<ReceiverChunks> out;
  for (size_t i : receiverIndices(only)) {
    const ReceiverMeshMemo& memo = updateMeshMemo(receivers_[i], meshCounters_);
    ReceiverChunks& entry = out.emplace_back();
    entry.face = receivers_[i].face;
    for (const auto& [key, chunk] : memo.chunks()) entry.chunks.push_back({key, chunk});
  }
  pruneMeshMemo();
  return out;
}

ReceiverMesh Engine::meshOf(FaceId face) {
  const auto it = receiverIndex_.find(face);
  if (it == receiverIndex_.end()) throw std::out_of_range("Engine::meshOf: the face is not a receiver");
  meshCounters_ = {};
  return meshReceiver(receivers_[it->second]);
}

ReceiverMesh Engine::meshReceiver(const Receiver& receiver) {
  const ReceiverMeshMemo& memo = updateMeshMemo(receiver, meshCounters_);
  ReceiverMesh result;
  result.face = receiver.face;
  result.normal = receiver.frame.normal;
  for (const auto& [key, chunk] : memo.chunks()) appendMesh(result, *chunk);
  return result;
}

const ReceiverMeshMemo& Engine::updateMeshMemo(const Receiver& receiver, MeshMemoCounters& counters) {
  ReceiverMeshMemo& memo = meshMemo_[receiver.face];
  const MeshSource source{receiver.face, receiver.frame, receiver.tree, receiver.values, receiver.perLight};
  memo.update(scene_, source, MeshGrid{meshSpacing(), meshChunkSquares_}, counters);
  return memo;
}

double Engine::meshSpacing() const {
  if (settings_.meshSpacing > 0) return settings_.meshSpacing;
  if (settings_.meshSpacing < 0) return 0;
  return scene_.bounds().diagonal() / EngineSettings::kDefaultSpacingDivisions;
}

void Engine::validate() const {
  for (const auto& order : orders_) order->validate();
  for (const auto& cube : cubes_) cube->validate();
  for (const Receiver& receiver : receivers_) receiver.tree.validate();
  // The cast relations mirror each other and name live faces and receivers.
  auto fail = [](const std::string& what) { throw std::logic_error("Engine: " + what); };
  for (const auto& [occluder, targets] : castOn_) {
    if (!findFace(scene_, occluder)) fail("castOn names a face not in the scene");
    for (FaceId target : targets) {
      if (!receiver(target)) fail("castOn names a face without a DM-tree");
      const auto by = castBy_.find(target);
      if (by == castBy_.end() || !by->second.count(occluder)) fail("castOn without its castBy entry");
    }
  }
  for (const auto& [target, occluders] : castBy_)
    for (FaceId occluder : occluders) {
      const auto on = castOn_.find(occluder);
      if (on == castOn_.end() || !on->second.count(target)) fail("castBy without its castOn entry");
    }
  for (size_t i = 0; i < receivers_.size(); ++i) {
    if (i && !(receivers_[i - 1].face < receivers_[i].face)) fail("receivers out of face order");
    const auto it = receiverIndex_.find(receivers_[i].face);
    if (it == receiverIndex_.end() || it->second != i) fail("receiver index out of date");
  }
  if (receiverIndex_.size() != receivers_.size()) fail("receiver index holds stale faces");
}

}  // namespace penumbra
