// Engine::apply's RELIGHT phase (paper §3.3): every vertex of the frame's relight set once,
// plus any live vertex whose slot holds no value for its position (one the tree did not
// report as new); counts what was created and what changed.
#include <algorithm>
#include <chrono>
#include <set>

#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"

namespace penumbra {

void Engine::relightDirty(const FrameWork& work, FrameResult& result) {
  const auto start = std::chrono::steady_clock::now();
  lastRelit_.clear();
  for (const auto& [face, vertices] : work.dirty.receivers()) {
    reach("relight");
    Receiver& receiver = receivers_[receiverIndex_.at(face)];
    const HalfEdgeMesh& mesh = receiver.tree.mesh();
    const size_t known = work.dirty.valueSlots(face, receiver.perLight.size());
    growSlots(receiver);
    // A receiver meshed from its lattice squares keeps no values; one that stops being so
    // has every live vertex lit (the scan below from slot 0).
    const bool leftLattice = chooseDisplay(receiver);
    if (receiver.fromLattice) {
      if (!vertices.empty() || work.dirty.topologyChanged(face)) result.changedReceivers.push_back(face);
      continue;
    }
    std::set<VertexId> relight;
    for (VertexId v : vertices)
      if (v.index < mesh.vertexSlots() && mesh.vertex(v).alive) relight.insert(v);
    // Vertex slots are append-only and positions never change, so only slots past `known`
    // can hold an unlit vertex, unless the tree was rebuilt (slots reused).
    const bool rebuiltTree = work.rebuiltTrees.count(face) || work.rebuild.count(face) || leftLattice;
    for (uint32_t i = rebuiltTree ? 0 : uint32_t(std::min(known, mesh.vertexSlots())); i < mesh.vertexSlots(); ++i) {
      const VertexId v(i);
      if (mesh.vertex(v).alive && !receiver.lit[i]) relight.insert(v);
    }
    for (VertexId v : relight) {
      const bool fresh = v.index >= known || !receiver.lit[v.index];
      const VertexIrradiance old = fresh ? VertexIrradiance{} : value(receiver, v);
      relightVertex(receiver, v);
      ++result.verticesRelit;
      if (fresh) ++result.verticesCreated;
      if (fresh || !sameValue(old, value(receiver, v))) ++result.verticesChanged;
    }
    if (!relight.empty() || work.dirty.topologyChanged(face)) result.changedReceivers.push_back(face);
    if (!relight.empty()) lastRelit_[face] = std::vector<VertexId>(relight.begin(), relight.end());
  }
  result.seconds.relight = secondsSince(start);
}

}  // namespace penumbra
