// The relight set of one frame (paper §3.3): per receiver, the DM vertices an edit
// created or whose surrounding occluder lists changed, and which trees changed shape.
// Plain data filled by Engine::apply during a frame; not thread-safe.
#pragma once

#include <map>
#include <set>
#include <vector>

#include "core/dmtree/dm_tree.h"
#include "core/scene/scene.h"

namespace penumbra {

class DirtySet {
 public:
  // A receiver whose tree an edit touched (its vertices are checked for new slots).
  void touch(FaceId receiver) { receivers_[receiver]; }
  void markTopology(FaceId receiver) { topology_.insert(receiver); }
  void addVertex(FaceId receiver, VertexId v) { receivers_[receiver].insert(v); }
  void addVertices(FaceId receiver, const std::vector<VertexId>& vertices) {
    receivers_[receiver].insert(vertices.begin(), vertices.end());
  }
  // Every vertex on the loop of each live cell.
  void addCells(FaceId receiver, const DmTree& tree, const std::vector<CellId>& cells) {
    std::set<VertexId>& out = receivers_[receiver];
    const HalfEdgeMesh& mesh = tree.mesh();
    for (CellId c : cells) {
      if (c.index >= mesh.cellSlots() || !mesh.cell(c).alive) continue;
      for (HalfEdgeId h : mesh.loop(c)) out.insert(mesh.halfEdge(h).origin);
    }
  }
  // How many vertex slots held values when the frame first touched the receiver (the
  // first note counts): slots past it may hold vertices nobody reported.
  void noteValueSlots(FaceId receiver, size_t slots) { valueSlots_.emplace(receiver, slots); }
  size_t valueSlots(FaceId receiver, size_t otherwise) const {
    const auto it = valueSlots_.find(receiver);
    return it == valueSlots_.end() ? otherwise : it->second;
  }
  // A receiver whose tree is gone or rebuilt: its pending vertices mean nothing now.
  void forget(FaceId receiver) {
    receivers_.erase(receiver);
    topology_.erase(receiver);
    valueSlots_.erase(receiver);
  }

  const std::map<FaceId, std::set<VertexId>>& receivers() const { return receivers_; }
  bool pending(FaceId receiver, VertexId v) const {
    const auto it = receivers_.find(receiver);
    return it != receivers_.end() && it->second.count(v) != 0;
  }
  bool topologyChanged(FaceId receiver) const { return topology_.count(receiver) != 0; }

 private:
  std::map<FaceId, std::set<VertexId>> receivers_;
  std::set<FaceId> topology_;
  std::map<FaceId, size_t> valueSlots_;
};

}  // namespace penumbra
