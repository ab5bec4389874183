// Engine::apply's REMOVE phase (paper §3.1): the leaving faces quit the orders and cubes,
// every DM-tree they shadowed loses their nodes and list entries (node deletion), and what
// that deletion re-split is queued for relighting.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <new>
#include <optional>
#include <tuple>

#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

void Engine::removeLeaving(const FramePlan& plan, FrameWork& work, FrameResult& result) {
  const auto start = std::chrono::steady_clock::now();
  for (size_t l = 0; l < scene_.lights().size(); ++l)
    for (FaceId face : plan.leavingFaces) {
      orders_[l]->removeFace(face);
      cubes_[l]->removeFace(face);
    }
  // Receivers of leaving faces are dropped; a moved face's slot is reused for its new tree,
  // so a move does not reorder the receivers.
  work.dropped.assign(receivers_.size(), false);
  // The leaving occluders: their faces and, for those that cast whole, the objects.
  std::vector<FaceId> leavingOccluders = plan.leavingFaces;
  for (uint32_t h : plan.leaving) leavingOccluders.push_back(wholeObject(h));
  for (FaceId face : leavingOccluders) {
    const auto on = castOn_.find(face);
    const std::set<FaceId> shadowed = on == castOn_.end() ? std::set<FaceId>{} : on->second;
    for (FaceId target : shadowed) {
      if (const auto by = castBy_.find(target); by != castBy_.end()) by->second.erase(face);
      if (plan.leaving.count(target.object) || work.rebuild.count(target)) continue;  // dropped or rebuilt anyway
      deleteOccluderNodes(face, target, work, result);
    }
    castOn_.erase(face);
    forgetReceived(face);
  }
  // The leaving objects' own trees go (a moved object's faces get fresh ones).
  for (FaceId face : plan.leavingReceivers) {
    const size_t i = receiverIndex_.at(face);
    budget_.change(usageOf(receivers_[i].tree, scene_.lights().size()), {});
    work.dropped[i] = true;
    work.freeSlots[face] = i;
    receiverIndex_.erase(face);
    work.dirty.forget(face);
    work.rebuild.erase(face);
    work.rebuiltTrees.erase(face);
  }
  for (FaceId face : work.rebuiltTrees)
    if (!work.rebuild.count(face)) ++result.treeRebuilds;
  result.seconds.remove = secondsSince(start);
}

void Engine::deleteOccluderNodes(FaceId occluder, FaceId target, FrameWork& work, FrameResult& result) {
  Receiver& receiver = receivers_[receiverIndex_.at(target)];
  DmTree& tree = receiver.tree;
  const size_t lights = scene_.lights().size();
  work.dirty.touch(target);
  // changedCells holds the cells that lost the face and those whose outline changed (a merged
  // cell's survivor among them), so every vertex whose surrounding lists changed is on a live one.
  try {
    for (size_t l = 0; l < lights; ++l) {
      const TreeUsage before = usageOf(tree, lights);
      const RemoveResult removed = tree.removeOccluder(uint32_t(l), occluder);
      budget_.change(before, usageOf(tree, lights));
      if (!removed.found) continue;
      result.nodesDeleted += removed.nodesRemoved;
      work.dirty.markTopology(target);
      if (removed.rebuilt) {
        // The tree rebuilt itself from its stored shadows: every handle is new.
        work.rebuiltTrees.insert(target);
        work.dirty.forget(target);
        work.dirty.touch(target);
        work.dirty.markTopology(target);
        receiver.lit.assign(receiver.lit.size(), 0);
        continue;
      }
      relightAfterRemoval(target, receiver, removed, work.dirty);
    }
  } catch (const ResourceLimitError&) {
    throw;  // a budget, not a geometric failure: never retried
  } catch (const std::bad_alloc&) {
    throw;  // no memory: a bigger rebuild would not help, the caller restores
  } catch (const std::exception&) {
    work.rebuild.insert(target);
    work.dirty.forget(target);
  }
}

void Engine::relightAfterRemoval(FaceId target, Receiver& receiver, const RemoveResult& removed, DirtySet& dirty) {
  const DmTree& tree = receiver.tree;
  const HalfEdgeMesh& mesh = tree.mesh();
  const double eps = scene_.tolerance().length();
  dirty.noteValueSlots(target, receiver.perLight.size());
  growSlots(receiver);
  dirty.touch(target);
  // Deleted vertices that held a current value for their position (not waiting to be
  // relit after an earlier deletion of this frame), by exact position.
  std::vector<std::tuple<double, double, uint32_t>> deleted;  // (x, y, slot), sorted
  for (VertexId v : removed.removedVertices) {
    const Vec2 p = tree.position(v);
    if (v.index < receiver.lit.size() && receiver.lit[v.index] && !dirty.pending(target, v))
      deleted.emplace_back(p.x, p.y, v.index);
  }
  std::sort(deleted.begin(), deleted.end());
  auto deletedAt = [&](const Vec2& p) -> std::optional<uint32_t> {
    const auto it = std::lower_bound(deleted.begin(), deleted.end(), std::tuple(p.x, p.y, uint32_t(0)));
    if (it == deleted.end() || std::get<0>(*it) != p.x || std::get<1>(*it) != p.y) return std::nullopt;
    return std::get<2>(*it);
  };
  // The penumbra's box first: most re-split cells lie far from it.
  Vec2 boxMin(INFINITY), boxMax(-INFINITY);
  for (const Vec2& q : removed.penumbra) {
    boxMin = glm::min(boxMin, q - Vec2(eps));
    boxMax = glm::max(boxMax, q + Vec2(eps));
  }
  auto inPenumbra = [&](const Vec2& p) {
    if (removed.penumbra.empty()) return true;
    if (glm::any(glm::lessThan(p, boxMin)) || glm::any(glm::greaterThan(p, boxMax))) return false;
    return contains(removed.penumbra, p, eps);
  };
  std::vector<bool> seen(mesh.vertexSlots(), false);
  auto settle = [&](VertexId v) {
    if (v.index >= mesh.vertexSlots() || seen[v.index] || !mesh.vertex(v).alive) return;
    seen[v.index] = true;
    const Vec2 p = tree.position(v);
    if (inPenumbra(p)) return dirty.addVertex(target, v);
    if (receiver.lit[v.index]) return;  // a survivor: its value stands
    const std::optional<uint32_t> was = deletedAt(p);
    if (!was) return dirty.addVertex(target, v);
    std::ranges::copy(receiver.perLight[*was], receiver.perLight[v.index].begin());
    receiver.lit[v.index] = 1;
    for (CellId c : tree.cellsAround(v)) receiver.tree.touch(c);  // corner values for meshing
  };
  std::vector<CellId> cells = removed.changedCells;
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  for (CellId c : cells) {
    if (c.index >= mesh.cellSlots() || !mesh.cell(c).alive) continue;
    const HalfEdgeId first = mesh.cell(c).edge;
    HalfEdgeId h = first;
    do {
      settle(mesh.halfEdge(h).origin);
      h = mesh.halfEdge(h).next;
    } while (h != first);
  }
  for (VertexId v : removed.newVertices) settle(v);
}

}  // namespace penumbra
