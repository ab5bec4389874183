// Engine::apply's ADD phase (paper §3.2): the entering faces join the orders and cubes, get
// DM-trees if they receive light, and cast both ways with the faces sharing their tiles, in
// front-to-back order among the faces involved.
#include <algorithm>
#include <chrono>
#include <map>
#include <set>
#include <tuple>

#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/illum/face_lookup.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

void Engine::addEntering(const FramePlan& plan, FrameWork& work, FrameResult& result) {
  const auto start = std::chrono::steady_clock::now();
  std::vector<const Face*> entering;
  for (uint32_t h : plan.entering)
    for (const Face& face : scene_.facesOfObject(h)) entering.push_back(&face);
  const size_t lights = scene_.lights().size();
  for (size_t l = 0; l < lights; ++l)
    for (const Face* face : entering) {
      orders_[l]->insertFace(*face);
      cubes_[l]->insertFace(*face);
    }
  for (const Face* face : entering)
    if (scene_.receivesLight(*face)) placeReceiver(*face, work);
  for (size_t l = 0; l < lights; ++l) castEntering(l, entering, work);
  recastFailed(work, result);
  result.seconds.add = secondsSince(start);
}

void Engine::placeReceiver(const Face& face, FrameWork& work) {
  const size_t lights = scene_.lights().size();
  if (const auto slot = work.freeSlots.find(face.id); slot != work.freeSlots.end()) {
    receivers_[slot->second] = makeReceiver(face);
    budget_.change({}, usageOf(receivers_[slot->second].tree, lights));
    work.dropped[slot->second] = false;
    receiverIndex_[face.id] = slot->second;
    work.freeSlots.erase(slot);
  } else {
    work.appendedOutOfOrder |= !receivers_.empty() && !(receivers_.back().face < face.id);
    receiverIndex_[face.id] = receivers_.size();
    receivers_.push_back(makeReceiver(face));
    budget_.change({}, usageOf(receivers_.back().tree, lights));
    work.dropped.push_back(false);
  }
  work.dirty.touch(face.id);
  work.dirty.markTopology(face.id);
}

void Engine::castEntering(size_t light, const std::vector<const Face*>& entering, FrameWork& work) {
  const FaceOrder& order = *orders_[light];
  // Front-to-back ranks among the faces involved only (FaceOrder::walkKey), so the whole walk
  // is not rebuilt for each frame.
  std::vector<std::pair<FaceId, FaceId>> pairs;  // (entering face, candidate)
  std::map<FaceId, FaceOrder::WalkKey> keys;
  for (const Face* face : entering) {
    if (!order.contains(face->id)) continue;
    keys[face->id];
    for (FaceId other : cubes_[light]->candidates(face->id)) {
      // Faces of one closed convex object never shadow each other (as in the build).
      if (!order.contains(other) || !scene_.mayShadow(face->id, other)) continue;
      keys[other];
      pairs.push_back({face->id, other});
    }
  }
  std::vector<std::pair<FaceOrder::WalkKey, FaceId>> byKey;
  for (auto& [face, key] : keys) byKey.push_back({order.walkKey(face), face});
  std::sort(byKey.begin(), byKey.end());
  std::map<FaceId, size_t> rank;
  for (size_t i = 0; i < byKey.size(); ++i) rank[byKey[i].second] = i;
  std::set<std::tuple<size_t, size_t, FaceId, FaceId>> attempts;  // ranks, occluder, receiver
  for (const auto& [face, other] : pairs) {
    attempts.insert({rank.at(face), rank.at(other), face, other});
    attempts.insert({rank.at(other), rank.at(face), other, face});
  }
  std::set<std::pair<FaceId, FaceId>> cast;  // a whole object casts once, at its first face's rank
  for (const auto& [occluderRank, receiverRank, occluder, target] : attempts) {
    const auto found = receiverIndex_.find(target);
    if (found == receiverIndex_.end() || work.rebuild.count(target)) continue;
    const FaceId caster =
        castingOccluder(scene_, light, occluder, *findFace(scene_, target), settings_.closedObjectsAsOne);
    if (!cast.insert({caster, target}).second) continue;
    Receiver& receiver = receivers_[found->second];
    const auto inserted = castPair(light, caster, receiver);
    if (!inserted) continue;
    work.dirty.touch(target);
    if (inserted->nodesAdded || !inserted->newVertices.empty()) work.dirty.markTopology(target);
    work.dirty.addCells(target, receiver.tree, inserted->changedCells);
    work.dirty.addVertices(target, inserted->newVertices);
  }
}

void Engine::recastFailed(FrameWork& work, FrameResult& result) {
  const size_t lights = scene_.lights().size();
  for (FaceId target : work.rebuild) {
    Receiver& receiver = receivers_[receiverIndex_.at(target)];
    forgetReceived(target);
    budget_.change(usageOf(receiver.tree, lights), {});
    receiver = makeReceiver(*findFace(scene_, target));
    budget_.change({}, usageOf(receiver.tree, lights));
    castAllOn(receiver);
    work.dirty.touch(target);
    work.dirty.markTopology(target);
    ++result.treeRebuilds;
  }
}

}  // namespace penumbra
