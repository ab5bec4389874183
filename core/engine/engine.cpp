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
#include <unordered_map>

#include "core/geom/clip.h"
#include "core/illum/face_lookup.h"
#include "core/mesh/cell_triangulation.h"
#include "core/mesh/lattice_split.h"
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

// Sums the lights' contributions like the reference: radiance-weighted factors,
// classes combined over the lights that reach the point (Umbra if none does).
VertexIrradiance sumLights(const Scene& scene, const std::vector<VertexLight>& lights,
                           const std::vector<bool>* dark = nullptr) {
  VertexIrradiance out;
  bool any = false;
  for (size_t l = 0; l < lights.size(); ++l) {
    const VertexLight& light = lights[l];
    out.comparisons += light.comparisons;
    if (!light.applies) continue;
    const bool isDark = dark && (*dark)[l];
    const LightClass cls = isDark ? LightClass::Umbra : light.lightClass;
    if (!isDark) out.irradiance += scene.lights()[l].radiance * light.factor;
    out.lightClass = any ? combine(out.lightClass, cls) : cls;
    any = true;
  }
  if (!any) out.lightClass = LightClass::Umbra;
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
    : scene_(std::move(scene)), settings_(settings), budget_(settings.limits) {
  budget_.checkFaces(scene_.faces().size());
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
    orders_.push_back(std::make_unique<FaceOrder>(scene_, l, settings_.limits.treeNodes));
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
    budget_.change({}, usageOf(receivers_.back().tree, scene_.lights().size()));
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
  receiver.tree.setNodeLimit(settings_.limits.treeNodes);
  for (size_t l = 0; l < scene_.lights().size(); ++l)
    if (const auto horizon = lightPlaneShadow(scene_, l, face, frame)) receiver.tree.insert(*horizon);
  return receiver;
}

std::optional<InsertResult> Engine::castPair(size_t light, const Face& occluder, Receiver& receiver) {
  const Face* face = findFace(scene_, receiver.face);
  if (!face) throw std::logic_error("Engine: receiver without a scene face");
  const auto shadow = castShadow(scene_, light, occluder, *face, receiver.frame);
  if (!shadow) return std::nullopt;
  const TreeUsage before = usageOf(receiver.tree, scene_.lights().size());
  InsertResult inserted = receiver.tree.insert(*shadow);
  budget_.change(before, usageOf(receiver.tree, scene_.lights().size()));
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

void Engine::recountBudget() {
  budget_.clear();
  for (const Receiver& receiver : receivers_) budget_.change({}, usageOf(receiver.tree, scene_.lights().size()));
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

namespace {

// Output vertices of one receiver: points within eps are one location (lattice
// cuts of a shared edge come from each side), and a location repeats once per
// distinct value (value discontinuities, dark cells). Ids are given in order of
// first appearance, so the output depends only on the sequence of calls.
class ReceiverMeshBuilder {
 public:
  ReceiverMeshBuilder(ReceiverMesh& mesh, const PlaneFrame& frame, double eps)
      : mesh_(mesh), frame_(frame), eps_(eps) {}

  uint32_t vertex(const Vec2& at, const VertexIrradiance& value) {
    const Key key{location(at), value.irradiance.x, value.irradiance.y, value.irradiance.z, value.lightClass};
    const auto [it, added] = index_.emplace(key, uint32_t(mesh_.positions.size()));
    if (added) {
      mesh_.positions.push_back(frame_.to3D(locations_[key.location]));
      mesh_.irradiance.push_back(value.irradiance);
      mesh_.classes.push_back(value.lightClass);
    }
    return it->second;
  }

 private:
  struct Key {
    uint32_t location;
    double r, g, b;
    LightClass lightClass;
    bool operator==(const Key& o) const {
      return location == o.location && r == o.r && g == o.g && b == o.b && lightClass == o.lightClass;
    }
  };
  // Hashes agree with ==: +0 and -0 hash alike.
  static size_t mix(size_t seed, size_t value) { return seed ^ (value + 0x9e3779b97f4a7c15ull + (seed << 6) + (seed >> 2)); }
  static size_t bits(double x) { return std::hash<double>{}(x == 0 ? 0.0 : x); }
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return mix(mix(mix(mix(k.location, bits(k.r)), bits(k.g)), bits(k.b)), size_t(k.lightClass));
    }
  };
  struct BucketHash {
    size_t operator()(const std::pair<long, long>& b) const { return mix(std::hash<long>{}(b.first), std::hash<long>{}(b.second)); }
  };

  // Buckets of side 2·eps: a point merges with the first earlier one within eps.
  uint32_t location(const Vec2& at) {
    const double side = 2 * eps_;
    const long x = long(std::floor(at.x / side)), y = long(std::floor(at.y / side));
    // A neighbour bucket farther than 1.25·eps along an axis holds no point within
    // eps: skipping it finds the same first match, with ~5 look-ups instead of 9.
    const double fx = at.x - double(x) * side, fy = at.y - double(y) * side;
    const long xFrom = fx > 1.25 * eps_ ? 0 : -1, xTo = side - fx > 1.25 * eps_ ? 0 : 1;
    const long yFrom = fy > 1.25 * eps_ ? 0 : -1, yTo = side - fy > 1.25 * eps_ ? 0 : 1;
    for (long dx = xFrom; dx <= xTo; ++dx)
      for (long dy = yFrom; dy <= yTo; ++dy) {
        const auto bucket = buckets_.find({x + dx, y + dy});
        if (bucket == buckets_.end()) continue;
        for (uint32_t id : bucket->second)
          if (glm::length(locations_[id] - at) <= eps_) return id;
      }
    const uint32_t id = uint32_t(locations_.size());
    locations_.push_back(at);
    buckets_[{x, y}].push_back(id);
    return id;
  }

  ReceiverMesh& mesh_;
  const PlaneFrame& frame_;
  double eps_;
  std::vector<Vec2> locations_;
  std::unordered_map<std::pair<long, long>, std::vector<uint32_t>, BucketHash> buckets_;
  std::unordered_map<Key, uint32_t, KeyHash> index_;
};

bool sameValues(const std::vector<VertexIrradiance>& a, const std::vector<VertexIrradiance>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i)
    if (!identicalValue(a[i], b[i])) return false;
  return true;
}

bool sameFrame(const PlaneFrame& a, const PlaneFrame& b) {
  return a.origin == b.origin && a.u == b.u && a.v == b.v && a.normal == b.normal;
}

}  // namespace

void Engine::CellMeshMemo::clearInputs() {
  outline.clear();
  occluders.clear();
  occluderPoints.clear();
  occluderSizes.clear();
  cornerFromCell.clear();
  cornerValues.clear();
  emitted.clear();
  triangles.clear();
  pieceChunks.clear();
  pieceEmitted.clear();
  pieceTriangles.clear();
}

bool Engine::CellMeshMemo::sameInputs(const CellMeshMemo& o) const {
  return valid && outline == o.outline && occluders == o.occluders && occluderSizes == o.occluderSizes &&
         occluderPoints == o.occluderPoints && cornerFromCell == o.cornerFromCell &&
         sameValues(cornerValues, o.cornerValues);
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
    const ReceiverMeshMemo& memo = updateMeshMemo(receivers_[i]);
    ReceiverChunks& entry = out.emplace_back();
    entry.face = receivers_[i].face;
    for (const auto& [key, chunk] : memo.chunks) entry.chunks.push_back({key, chunk});
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
  const ReceiverMeshMemo& memo = updateMeshMemo(receiver);
  ReceiverMesh result;
  result.face = receiver.face;
  result.normal = receiver.frame.normal;
  for (const auto& [key, chunk] : memo.chunks) appendMesh(result, *chunk);
  return result;
}

const Engine::ReceiverMeshMemo& Engine::updateMeshMemo(const Receiver& receiver) {
  const double eps = scene_.tolerance().length();
  const double spacing = meshSpacing();
  const int chunkSquares = meshChunkSquares_;
  const double chunkSide = spacing * chunkSquares;  // 0: one chunk
  const size_t lightCount = scene_.lights().size();
  const DmTree& tree = receiver.tree;
  const HalfEdgeMesh& halfEdges = tree.mesh();
  const Vec3 normal = receiver.frame.normal;

  // The memo is only valid for the same face frame, lattice, chunks and tolerance.
  ReceiverMeshMemo& memo = meshMemo_[receiver.face];
  if (!sameFrame(memo.frame, receiver.frame) || memo.spacing != spacing || memo.eps != eps ||
      memo.chunkSquares != chunkSquares) {
    memo = ReceiverMeshMemo{};
    memo.frame = receiver.frame;
    memo.spacing = spacing;
    memo.eps = eps;
    memo.chunkSquares = chunkSquares;
  }
  const uint64_t stamp = HalfEdgeMesh::stampNow();

  // Chunks whose cells changed; the memo's old pieces and the new ones both count.
  // A cell's pieces leave or enter the chunks' cell lists (kept in cell order).
  std::set<MeshChunkKey> dirty;
  auto chunksOf = [&](uint32_t index) {
    const CellMeshMemo& m = memo.cells[index];
    return m.valid ? std::set<MeshChunkKey>(m.pieceChunks.begin(), m.pieceChunks.end()) : std::set<MeshChunkKey>{};
  };
  auto leaveChunks = [&](uint32_t index) {
    for (const MeshChunkKey& key : chunksOf(index)) {
      dirty.insert(key);
      std::vector<uint32_t>& cells = memo.chunkCells[key];
      const auto at = std::lower_bound(cells.begin(), cells.end(), index);
      if (at != cells.end() && *at == index) cells.erase(at);
    }
  };
  auto enterChunks = [&](uint32_t index) {
    for (const MeshChunkKey& key : chunksOf(index)) {
      dirty.insert(key);
      std::vector<uint32_t>& cells = memo.chunkCells[key];
      cells.insert(std::lower_bound(cells.begin(), cells.end(), index), index);
    }
  };
  for (size_t i = halfEdges.cellSlots(); i < memo.cells.size(); ++i) leaveChunks(uint32_t(i));  // a smaller rebuilt tree
  memo.cells.resize(halfEdges.cellSlots());

  // A point is on a value discontinuity (D0) when an occluder of a cell around it
  // has its plane through it (it touches the receiver there): it then takes its
  // value per side, as the limit from each cell. "Through it" is the geometric
  // predicate (length tolerance), not onPlane(): a point within onPlane() of the
  // plane but off the contact line (e.g. on a line meeting it at a shallow angle
  // near a footprint corner) lies inside one side, where the value is the point
  // value (the face does not shadow it, SCENE_FORMAT.md), with no other side's
  // copy to carry that value.
  auto onContact = [&](const Vec3& p, const OccluderList& list) {
    for (const OccluderEntry& entry : list) {
      const Face* face = findFace(scene_, entry.face);
      if (face && std::abs(face->plane.signedDistance(p)) <= eps) return true;
    }
    return false;
  };
  std::vector<int8_t> vertexContact(halfEdges.vertexSlots(), -1);  // -1: not asked yet
  auto onContactAround = [&](VertexId v) {
    int8_t& known = vertexContact[v.index];
    if (known < 0) {
      known = 0;
      const Vec3 p = receiver.frame.to3D(tree.position(v));
      for (CellId c : tree.cellsAround(v))
        if (onContact(p, tree.occluders(c))) {
          known = 1;
          break;
        }
    }
    return known == 1;
  };
  auto chunkOf = [&](const Polygon2& piece) {
    if (!(chunkSide > 0)) return MeshChunkKey{};
    Vec2 middle{0.0};
    for (const Vec2& q : piece) middle += q;
    middle /= double(piece.size());
    return MeshChunkKey{int64_t(std::floor(middle.x / chunkSide)), int64_t(std::floor(middle.y / chunkSide))};
  };

  // Cells touched since the last call: lit again unless every input is equal.
  CellMeshMemo inputs;  // this cell's inputs; swapped into the memo when lit afresh
  std::vector<bool> dark(lightCount);
  std::vector<VertexId> corners;
  for (uint32_t index = 0; index < halfEdges.cellSlots(); ++index) {
    const CellId c(index);
    const HalfEdgeMesh::Cell& cell = halfEdges.cell(c);
    CellMeshMemo& slot = memo.cells[index];
    if (cell.touched <= memo.stamp && (slot.valid || !cell.alive)) {
      if (cell.alive) ++meshCounters_.cellsReused;
      continue;
    }
    if (!cell.alive) {
      leaveChunks(index);
      slot = CellMeshMemo{};
      continue;
    }
    const OccluderList& list = cell.occluders;
    std::fill(dark.begin(), dark.end(), false);
    for (const OccluderEntry& entry : list)
      if (entry.umbra) dark[entry.light] = true;
    const bool anyDark = std::find(dark.begin(), dark.end(), true) != dark.end();

    // The inputs this cell's triangles depend on.
    inputs.clearInputs();
    corners.clear();
    for (HalfEdgeId h : halfEdges.loop(c)) corners.push_back(halfEdges.halfEdge(h).origin);
    for (VertexId v : corners) inputs.outline.push_back(tree.position(v));
    inputs.occluders = list;
    for (const OccluderEntry& entry : list) {
      const Face* face = findFace(scene_, entry.face);
      inputs.occluderSizes.push_back(face ? uint32_t(face->polygon.size()) : 0);
      if (face) inputs.occluderPoints.insert(inputs.occluderPoints.end(), face->polygon.begin(), face->polygon.end());
    }
    for (VertexId v : corners) {
      const bool fromCell = onContactAround(v);
      inputs.cornerFromCell.push_back(fromCell ? 1 : 0);
      inputs.cornerValues.push_back(fromCell ? VertexIrradiance{}
                                    : anyDark ? sumLights(scene_, receiver.perLight[v.index], &dark)
                                              : receiver.values[v.index]);
    }
    if (slot.sameInputs(inputs)) {
      ++meshCounters_.cellsReused;
      continue;
    }
    ++meshCounters_.cellsLit;
    leaveChunks(index);
    const Polygon2& polygon = inputs.outline;
    Vec3 centre{0.0};
    for (const Vec2& q : polygon) centre += receiver.frame.to3D(q);
    centre /= double(polygon.size());

    // The value of a point of this cell's closure, as seen from this cell.
    auto valueAt = [&](const Vec2& q) {
      const Vec3 p = receiver.frame.to3D(q);
      for (size_t i = 0; i < polygon.size(); ++i) {
        if (polygon[i] != q) continue;
        if (inputs.cornerFromCell[i]) return illuminatePointFromCell(scene_, p, normal, centre - p, list);
        return inputs.cornerValues[i];
      }
      // A lattice point: lit exactly from this cell's list (cases 2 and 3 keep it
      // dark in a light's umbra).
      if (onContact(p, list)) return illuminatePointFromCell(scene_, p, normal, centre - p, list);
      return illuminatePoint(scene_, p, normal, {&list});
    };

    for (const Polygon2& piece : splitByLattice(polygon, spacing, eps)) {
      inputs.pieceChunks.push_back(chunkOf(piece));
      inputs.pieceEmitted.push_back(uint32_t(inputs.emitted.size()));
      inputs.pieceTriangles.push_back(uint32_t(inputs.triangles.size()));
      std::vector<uint32_t> pieceCorners;
      for (const Vec2& q : piece) {
        pieceCorners.push_back(uint32_t(inputs.emitted.size()));
        inputs.emitted.push_back({q, valueAt(q)});
      }
      const CellTriangulation triangulation = triangulateConvexCell(piece, eps);
      if (triangulation.usesCentre) {
        Vec2 middle{0.0};
        for (const Vec2& q : piece) middle += q;
        middle /= double(piece.size());
        pieceCorners.push_back(uint32_t(inputs.emitted.size()));
        inputs.emitted.push_back(
            {middle, illuminatePoint(scene_, receiver.frame.to3D(middle), normal, {&list})});
      }
      for (const auto& t : triangulation.triangles)
        inputs.triangles.push_back({pieceCorners[t[0]], pieceCorners[t[1]], pieceCorners[t[2]]});
    }
    inputs.pieceEmitted.push_back(uint32_t(inputs.emitted.size()));
    inputs.pieceTriangles.push_back(uint32_t(inputs.triangles.size()));
    inputs.valid = true;
    std::swap(slot, inputs);  // the old slot's buffers are reused for the next cell
    enterChunks(index);
  }
  memo.stamp = stamp;

  // The changed chunks are assembled again from their cells' pieces, in cell order;
  // the builder sees the same calls in the same order as for a fresh mesh.
  if (!dirty.empty()) {
    struct ChunkAssembly {
      ReceiverMesh mesh;
      ReceiverMeshBuilder builder;
      ChunkAssembly(const Receiver& r, double eps) : builder(mesh, r.frame, eps) {
        mesh.face = r.face;
        mesh.normal = r.frame.normal;
      }
    };
    std::vector<uint32_t> ids;
    for (const MeshChunkKey& key : dirty) {
      ChunkAssembly assembly(receiver, eps);
      auto listed = memo.chunkCells.find(key);
      if (listed != memo.chunkCells.end())
        for (uint32_t index : listed->second) {
          const CellMeshMemo& m = memo.cells[index];
          for (size_t j = 0; j < m.pieceChunks.size(); ++j) {
            if (m.pieceChunks[j] != key) continue;
            ids.resize(m.emitted.size());
            for (uint32_t e = m.pieceEmitted[j]; e < m.pieceEmitted[j + 1]; ++e)
              ids[e] = assembly.builder.vertex(m.emitted[e].first, m.emitted[e].second);
            for (uint32_t t = m.pieceTriangles[j]; t < m.pieceTriangles[j + 1]; ++t)
              assembly.mesh.triangles.push_back({ids[m.triangles[t][0]], ids[m.triangles[t][1]], ids[m.triangles[t][2]]});
          }
        }
      if (listed != memo.chunkCells.end() && listed->second.empty()) memo.chunkCells.erase(listed);
      if (assembly.mesh.triangles.empty())
        memo.chunks.erase(key);
      else
        memo.chunks[key] = std::make_shared<const ReceiverMesh>(std::move(assembly.mesh));
    }
  }
  meshCounters_.chunksMeshed += dirty.size();
  for (const auto& entry : memo.chunks) meshCounters_.chunksKept += dirty.count(entry.first) ? 0 : 1;
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
