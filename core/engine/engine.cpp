#include "core/engine/engine.h"

#include <algorithm>
#include <atomic>
#include <mutex>
#include <cmath>
#include <limits>
#include <chrono>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <tuple>

#include "core/engine/cube_grid.h"
#include "core/engine/seconds_since.h"
#include "core/geom/clip.h"
#include "core/illum/face_lookup.h"
#include "core/illum/light_sum.h"
#include "core/mesh/lattice_display_rule.h"
#include "core/shadow/cast_shadow.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

namespace {

using Clock = std::chrono::steady_clock;

// One shadow a receiver takes during the build: from `light`, of `occluder` (a face or a
// whole object).
struct ReceiverCast {
  uint32_t light;
  FaceId occluder;
};

// The build's casts split by receiver (index into `receiverIndex`'s values), each receiver's in
// the paper's order: every candidate pair of the overlap cubes both ways (§2.3), occluders
// front to back, light by light; with `wholeObjects`, a closed convex object that casts on a
// receiver as one occluder does so once, at the rank of its first face there. Counts the
// pairs and attempts in `stats`.
std::vector<std::vector<ReceiverCast>> castSequences(
    const Scene& scene, const std::vector<std::unique_ptr<FaceOrder>>& orders,
    const std::vector<std::unique_ptr<OverlapCube>>& cubes, const std::map<FaceId, size_t>& receiverIndex,
    bool wholeObjects, BuildStats& stats) {
  std::vector<std::vector<ReceiverCast>> casts(receiverIndex.size());
  for (size_t l = 0; l < scene.lights().size(); ++l) {
    const FaceOrder& order = *orders[l];
    // A mesh casting whole on its own faces (object_shadow.h) does so once per face, at the
    // lowest rank of its faces sharing a tile with it (what the sort and unique below
    // would keep of one attempt per pair): those pairs are not listed at all (a 6,000-face
    // model has millions). Its faces with nothing in front cast nothing on each other.
    std::map<uint32_t, bool> ownWhole;
    auto castsOnItselfWhole = [&](uint32_t object) {
      auto [it, added] = ownWhole.try_emplace(object, false);
      if (added && wholeObjects) it->second = castsWholeOnItself(scene, l, object);
      return it->second;
    };
    const auto pairs = cubes[l]->candidatePairs(castsOnItselfWhole);
    stats.candidatePairs += pairs.size();
    struct Attempt {
      size_t occluderRank, receiverRank;
      FaceId occluder, receiver;
    };
    std::vector<Attempt> attempts;
    // One attempt of a face, listed as what it casts as (a face of a mesh may cast as the whole
    // object, at this face's rank). A face that stays a face and has nothing in front of the
    // receiver's plane casts nothing (castShadow) and is not listed: a model lying wholly
    // behind the faces of another would list each of its faces on each of them.
    const auto addAttempt = [&](FaceId occluder, const Face* face, FaceId receiver, const Face* target) {
      FaceId caster = occluder;
      if (wholeObjects && target && scene.castsWhole(occluder.object))
        caster = castingOccluder(scene, l, occluder, *target, true);
      if (caster == occluder && face && target && !reachesFrontOf(*face, *target, scene.tolerance())) return;
      attempts.push_back({order.rank(occluder), order.rank(receiver), caster, receiver});
    };
    for (const auto& [a, b] : pairs) {
      if (!scene.mayShadow(a, b)) {  // faces of one closed convex object
        ++stats.closedConvexPairs;
        continue;
      }
      if (!order.contains(a) || !order.contains(b)) continue;
      const Face *faceA = findFace(scene, a), *faceB = findFace(scene, b);
      addAttempt(a, faceA, b, faceB);
      addAttempt(b, faceB, a, faceA);
    }
    const auto own = cubes[l]->lowestSameObjectPartner(
        [&](uint32_t object) { return castsOnItselfWhole(object); },
        [&](FaceId face) { return order.contains(face) ? order.rank(face) : SIZE_MAX; });
    for (const auto& [receiver, rank] : own) {
      const Face* face = receiverIndex.count(receiver) ? findFace(scene, receiver) : nullptr;
      if (face && castsAsOneOccluder(scene, l, receiver.object, *face))
        attempts.push_back({rank, order.rank(receiver), wholeObject(receiver.object), receiver});
    }
    if (wholeObjects) {
      std::sort(attempts.begin(), attempts.end(), [](const Attempt& x, const Attempt& y) {
        return std::tie(x.occluder, x.receiver, x.occluderRank, x.receiverRank) <
               std::tie(y.occluder, y.receiver, y.occluderRank, y.receiverRank);
      });
      attempts.erase(std::unique(attempts.begin(), attempts.end(), [](const Attempt& x, const Attempt& y) {
                       return x.occluder == y.occluder && x.receiver == y.receiver;
                     }),
                     attempts.end());
    }
    std::sort(attempts.begin(), attempts.end(), [](const Attempt& x, const Attempt& y) {
      return std::tie(x.occluderRank, x.receiverRank) < std::tie(y.occluderRank, y.receiverRank);
    });
    for (const Attempt& attempt : attempts) {
      const auto found = receiverIndex.find(attempt.receiver);
      if (found == receiverIndex.end()) continue;
      casts[found->second].push_back({uint32_t(l), attempt.occluder});
      ++stats.castAttempts;
    }
  }
  return casts;
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
  shadow.cullsBehind = true;  // behind the light's plane no point gets its light
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
    : scene_(std::move(scene)),
      settings_(settings),
      parallel_(settings.threads),
      budget_(settings.limits) {
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
  stats_ = BuildStats{};
  stats_.faces = scene_.faces().size();
  stats_.lights = scene_.lights().size();
  buildOrdersAndCubes(progress);

  // One DM-tree per receiving face.
  const auto start = Clock::now();
  SharedProgress receiverReport(progress, "receivers", scene_.faces().size(),
                                std::max<size_t>(1, scene_.faces().size() / 100));
  for (const Face& face : scene_.faces()) {
    receiverReport.add(1);
    if (!scene_.receivesLight(face)) continue;
    receiverIndex_[face.id] = receivers_.size();
    receivers_.push_back(makeReceiver(face));
    budget_.change({}, usageOf(receivers_.back().tree, scene_.lights().size()));
  }
  receiverReport.finish();
  stats_.receivers = receivers_.size();
  // Cast every pair, then illuminate every vertex (§2.3, §2.4), receiver by receiver.
  castAndIlluminateAll(start, progress);
  countBuild();
}

void Engine::buildOrdersAndCubes(const EngineProgress& progress) {
  const size_t lightCount = scene_.lights().size();
  // Front-to-back orders (§2.1), one light per thread.
  auto start = Clock::now();
  orders_.resize(lightCount);
  SharedProgress orderReport(progress, "ordering", lightCount, 1);
  parallel_.forEach(lightCount, [&](size_t l) {
    orders_[l] = std::make_unique<FaceOrder>(scene_, l, settings_.limits.treeNodes);
    orderReport.add(1);
  });
  orderReport.finish();
  for (const auto& order : orders_) stats_.orderFragments += order->counters().fragments;
  stats_.seconds.ordering = secondsSince(start);

  // Shadow overlap cubes (§2.2).
  start = Clock::now();
  cubes_.resize(lightCount);
  SharedProgress cubeReport(progress, "cube", lightCount, 1);
  parallel_.forEach(lightCount, [&](size_t l) {
    OverlapCubeSettings cubeSettings;
    cubeSettings.grid = settings_.overlapGrid > 0 ? settings_.overlapGrid
                                                  : overlapGridFor(scene_, l, settings_.closedObjectsAsOne);
    cubes_[l] = std::make_unique<OverlapCube>(scene_, l, cubeSettings);
    cubeReport.add(1);
  });
  cubeReport.finish();
  for (const auto& cube : cubes_) stats_.tiles += cube->tileCount();
  stats_.seconds.cube = secondsSince(start);
}

void Engine::castAndIlluminateAll(Clock::time_point start, const EngineProgress& progress) {
  // A receiver's tree depends only on the sequence of shadows it receives, so receivers cast
  // their own sequences in parallel. A receiver's vertices depend only on its own tree, so each
  // is illuminated as soon as its casts are in: the other threads light small receivers while
  // the floor, one long task, is still being cast (a step boundary left them idle; sparse 150
  // cubes 5 % faster at 2 threads).
  stats_.castAttempts = 0;
  std::vector<std::vector<ReceiverCast>> casts = castSequences(scene_, orders_, cubes_, receiverIndex_, settings_.closedObjectsAsOne, stats_);
  std::vector<std::vector<FaceId>> shadowedBy(receivers_.size());  // occluders that cast, per receiver
  std::mutex progressMutex;  // both steps report at once
  // Reported per cast (about 256 reports in all): one receiver, the floor, may take most casts.
  SharedProgress castReport(progress, "casting", stats_.castAttempts,
                            std::max<size_t>(1, stats_.castAttempts / 256), &progressMutex);
  // Counts vertices lit, of those of the receivers cast so far: its total grows while casting
  // runs. One receiver, the floor under a model, may hold most of them.
  SharedProgress lightReport(progress, "illumination", 0, kVerticesPerBeat, &progressMutex);
  std::vector<double> castSeconds(receivers_.size()), lightSeconds(receivers_.size());
  const std::function<void()> castBeat = progress ? std::function<void()>([&] { castReport.beat(); }) : nullptr;
  parallel_.forEach(receivers_.size(), [&](size_t r) {
    const auto castStart = Clock::now();
    for (size_t i = 0; i < casts[r].size(); ++i) {
      const ReceiverCast& cast = casts[r][i];
      // A beat from inside one cast too: a model's shadow on the floor is one cast of seconds.
      if (castInto(cast.light, cast.occluder, receivers_[r], castBeat)) shadowedBy[r].push_back(cast.occluder);
      castReport.add(1);
      if (i % kCastsPerBeat == kCastsPerBeat - 1) castReport.beat();  // the floor takes most casts
    }
    receivers_[r].tree.shrinkToFit();
    std::vector<ReceiverCast>().swap(casts[r]);
    const auto lightStart = Clock::now();
    castSeconds[r] = std::chrono::duration<double>(lightStart - castStart).count();
    illuminate(receivers_[r], &lightReport);
    lightSeconds[r] = secondsSince(lightStart);
  });
  castReport.finish();
  lightReport.finish();
  splitStepSeconds(secondsSince(start), castSeconds, lightSeconds);
  for (size_t r = 0; r < receivers_.size(); ++r) {
    stats_.pairsWithShadow += shadowedBy[r].size();
    for (FaceId occluder : shadowedBy[r]) {
      castOn_[occluder].insert(receivers_[r].face);
      castBy_[receivers_[r].face].insert(occluder);
    }
  }
}

void Engine::splitStepSeconds(double wall, const std::vector<double>& castSeconds,
                              const std::vector<double>& lightSeconds) {
  // The two steps overlap, so each gets the share of the wall time its tasks took.
  double cast = 0, light = 0;
  for (double s : castSeconds) cast += s;
  for (double s : lightSeconds) light += s;
  const double castShare = cast + light > 0 ? cast / (cast + light) : 0.5;
  stats_.seconds.castingAndMerging = wall * castShare;
  stats_.seconds.illumination = wall - stats_.seconds.castingAndMerging;
}

void Engine::countBuild() {
  for (const Receiver& receiver : receivers_) {
    stats_.treeNodes += receiver.tree.internalNodeCount();
    stats_.cells += receiver.tree.cellCount();
    if (receiver.fromLattice) {  // values not computed (illuminate)
      stats_.vertices += receiver.tree.vertexCount();
      stats_.latticeVertices += receiver.tree.vertexCount();
      continue;
    }
    for (VertexId v : receiver.tree.vertices()) {
      const VertexIrradiance value = this->value(receiver, v);
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
  Receiver receiver{face.id, frame, DmTree(polygonInFrame(face.polygon, frame), scene_.tolerance()), {}, {}};
  receiver.tree.setNodeLimit(settings_.limits.treeNodes);
  receiver.tree.setUmbraCulling(settings_.umbraCulling);
  for (size_t l = 0; l < scene_.lights().size(); ++l)
    if (const auto horizon = lightPlaneShadow(scene_, l, face, frame)) receiver.tree.insert(*horizon);
  return receiver;
}

std::optional<InsertResult> Engine::castInto(size_t light, FaceId occluder, Receiver& receiver,
                                             const std::function<void()>& beat) {
  const Face* face = findFace(scene_, receiver.face);
  if (!face) throw std::logic_error("Engine: receiver without a scene face");
  std::optional<SingleShadow> shadow;
  if (isWholeObject(occluder)) {
    shadow = castObjectShadow(scene_, light, occluder.object, *face, receiver.frame);
  } else {
    const Face* occluderFace = findFace(scene_, occluder);
    if (!occluderFace) throw std::logic_error("Engine: occluder without a scene face");
    shadow = castShadow(scene_, light, *occluderFace, *face, receiver.frame, settings_.silhouetteLinesOnly);
  }
  if (!shadow) return std::nullopt;
  const TreeUsage before = usageOf(receiver.tree, scene_.lights().size());
  InsertResult inserted = receiver.tree.insert(*shadow, beat);
  budget_.change(before, usageOf(receiver.tree, scene_.lights().size()));
  return inserted;
}

std::optional<InsertResult> Engine::castPair(size_t light, FaceId occluder, Receiver& receiver) {
  auto inserted = castInto(light, occluder, receiver);
  if (!inserted) return std::nullopt;
  castOn_[occluder].insert(receiver.face);
  castBy_[receiver.face].insert(occluder);
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
      if (order.contains(candidate) && scene_.mayShadow(candidate, receiver.face))
        occluders.push_back(
            {order.rank(candidate), castingOccluder(scene_, l, candidate, *face, settings_.closedObjectsAsOne)});
    std::sort(occluders.begin(), occluders.end());
    std::set<FaceId> cast;  // a whole object casts once, at its first face's rank (as in the build)
    for (const auto& [rank, occluder] : occluders)
      if (cast.insert(occluder).second) castPair(l, occluder, receiver);
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

void Engine::growSlots(Receiver& receiver) const {
  const size_t slots = receiver.tree.mesh().vertexSlots();
  if (receiver.perLight.size() >= slots) return;
  receiver.perLight.resize(slots, scene_.lights().size());
  receiver.lit.resize(slots, 0);
}

bool Engine::chooseDisplay(Receiver& receiver) const {
  const bool lattice =
      displaysFromLattice(scene_, MeshSource{receiver.face, receiver.frame, receiver.tree, receiver.perLight}, meshGrid());
  const bool wasLattice = receiver.fromLattice;
  receiver.fromLattice = lattice;
  // Values kept from before are not kept up to date while the squares mesh it: dropped.
  if (lattice && !wasLattice) receiver.lit.assign(receiver.lit.size(), 0);
  return wasLattice && !lattice;
}

void Engine::illuminate(Receiver& receiver, SharedProgress* report) const {
  chooseDisplay(receiver);
  const size_t slots = receiver.tree.mesh().vertexSlots();
  // Headroom for a big receiver only: its first edits then grow its arrays in place instead of
  // moving every value, and the untouched tail of a large array costs no memory until used. A
  // small receiver's arrays share pages with other data, so headroom there would be resident
  // (thousands of small receivers), and moving them is cheap.
  const size_t capacity = slots >= kHeadroomMinSlots ? slots + slots / 4 : slots;
  receiver.perLight.reserve(capacity, scene_.lights().size());
  receiver.lit.reserve(capacity);
  receiver.perLight.assign(slots, scene_.lights().size());
  receiver.lit.assign(slots, 0);
  if (receiver.fromLattice) return;  // its display does not read them (Engine::value computes one)
  // Vertices in parallel (a dense scene's floor holds most of them); each writes its own slots.
  const std::vector<VertexId> vertices = receiver.tree.vertices();
  if (report) report->grow(vertices.size());
  std::atomic<size_t> lit{0};
  parallel_.forEach(vertices.size(), [&](size_t i) {
    computeVertex(receiver, vertices[i]);
    if (report && (lit.fetch_add(1) + 1) % kVerticesPerBeat == 0) report->add(kVerticesPerBeat);
  }, 16);
  if (report) report->add(vertices.size() % kVerticesPerBeat);
  // Every cell is new, so its corner values changed: the memo's test is the stamp.
  for (VertexId v : vertices)
    for (CellId c : receiver.tree.cellsAround(v)) receiver.tree.touch(c);
}

void Engine::relightVertex(Receiver& receiver, VertexId v) const {
  computeVertex(receiver, v);
  for (CellId c : receiver.tree.cellsAround(v)) receiver.tree.touch(c);  // their corner values may have changed
}

void Engine::computeVertex(Receiver& receiver, VertexId v) const {
  valuesAt(receiver, v, receiver.perLight[v.index]);
  receiver.lit[v.index] = 1;
}

void Engine::valuesAt(const Receiver& receiver, VertexId v, std::span<VertexLight> out) const {
  const DmTree& tree = receiver.tree;
  std::vector<const OccluderList*> lists;
  for (CellId c : tree.cellsAround(v)) lists.push_back(&tree.occluders(c));
  const Vec3 p = receiver.frame.to3D(tree.position(v));
  const Vec3 shading = shadingNormalAt(scene_, receiver.face, receiver.frame.normal, p);
  for (size_t l = 0; l < out.size(); ++l) out[l] = illuminateVertex(scene_, l, p, receiver.frame.normal, shading, lists);
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

std::vector<FaceId> Engine::receiverFaces() const {
  std::vector<FaceId> faces;
  for (const Receiver& r : receivers_) faces.push_back(r.face);
  return faces;
}

VertexIrradiance Engine::value(const Receiver& receiver, VertexId v) const {
  if (v.index < receiver.lit.size() && receiver.lit[v.index]) return sumLights(scene_, receiver.perLight[v.index]);
  // Not kept (a receiver meshed from its lattice squares): lit now, the same evaluation.
  std::vector<VertexLight> row(scene_.lights().size());
  valuesAt(receiver, v, row);
  return sumLights(scene_, row);
}

std::vector<MeshSource> Engine::meshSources(const std::vector<FaceId>& only) const {
  std::vector<size_t> indices;
  for (FaceId face : only)
    if (const auto it = receiverIndex_.find(face); it != receiverIndex_.end()) indices.push_back(it->second);
  std::sort(indices.begin(), indices.end());
  indices.erase(std::unique(indices.begin(), indices.end()), indices.end());
  std::vector<MeshSource> sources;
  sources.reserve(indices.size());
  for (size_t i : indices) {
    const Receiver& r = receivers_[i];
    sources.push_back({r.face, r.frame, r.tree, r.perLight, r.fromLattice});
  }
  return sources;
}

std::vector<MeshSource> Engine::meshSources() const {
  std::vector<MeshSource> sources;
  sources.reserve(receivers_.size());
  for (const Receiver& r : receivers_) sources.push_back({r.face, r.frame, r.tree, r.perLight, r.fromLattice});
  return sources;
}

void Engine::updateDisplayMemo(const std::vector<MeshSource>& sources, const EngineProgress& progress) {
  displayMemo_.update(scene_, sources, meshGrid(), parallel_, progress);
}

void Engine::pruneDisplayMemo() {
  displayMemo_.keepOnly([&](FaceId face) { return receiverIndex_.count(face) > 0; });
}

Mesh Engine::mesh(const EngineProgress& progress) {
  const auto start = Clock::now();
  const std::vector<MeshSource> sources = meshSources();
  updateDisplayMemo(sources, progress);
  Mesh out = displayMemo_.assemble(sources, meshGrid().refine.tolerance);
  pruneDisplayMemo();
  stats_.seconds.triangulation = secondsSince(start);
  return out;
}

Mesh Engine::mesh(const std::vector<FaceId>& only) {
  const std::vector<MeshSource> sources = meshSources(only);
  updateDisplayMemo(sources);
  Mesh out = displayMemo_.assemble(sources, meshGrid().refine.tolerance);
  pruneDisplayMemo();
  return out;
}

std::vector<Engine::ReceiverChunks> Engine::meshChunks(const std::vector<FaceId>& only, const EngineProgress& progress) {
  const std::vector<MeshSource> sources = meshSources(only);
  updateDisplayMemo(sources, progress);
  std::vector<ReceiverChunks> out;
  for (const MeshSource& source : sources) {
    ReceiverChunks& entry = out.emplace_back();
    entry.face = source.face;
    for (const auto& [key, chunk] : displayMemo_.chunksOf(source.face)) entry.chunks.push_back({key, chunk});
  }
  pruneDisplayMemo();
  return out;
}

ReceiverMesh Engine::meshOf(FaceId face) {
  if (!receiverIndex_.count(face)) throw std::out_of_range("Engine::meshOf: the face is not a receiver");
  const std::vector<MeshSource> sources = meshSources({face});
  updateDisplayMemo(sources);
  return displayMemo_.meshOf(sources.front());
}

MeshGrid Engine::meshGrid() const {
  RefineSettings refine;
  refine.tolerance = std::max(0.0, settings_.meshTolerance);
  refine.minEdge = scene_.bounds().diagonal() / settings_.meshRefineMinEdgeDivisions;
  refine.maxPoints = EngineSettings::kRefineMaxPoints;
  const double latticeTolerance = refine.tolerance > 0 ? refine.tolerance : EngineSettings::kRecommendedMeshTolerance;
  return MeshGrid{meshSpacing(), meshChunkSquares_, refine, settings_.meshLatticeAbove, latticeTolerance};
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
    if (isWholeObject(occluder) ? !scene_.castsWhole(occluder.object) : !findFace(scene_, occluder))
      fail("castOn names a face or whole object not in the scene");
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
