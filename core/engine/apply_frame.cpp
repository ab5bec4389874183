// Engine::apply: checking a frame, then updating the shadow state.
#include <chrono>

#include "core/engine/engine.h"

namespace penumbra {

Scene Engine::sceneAfter(const Frame& frame) const {
  Scene next = scene_;
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    try {
      switch (edit.op) {
        case Edit::Op::Move: {
          const auto index = next.findObject(edit.id);
          if (!index) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          next.setTransform(next.handleOf(*index), edit.transform);
          break;
        }
        case Edit::Op::Remove: {
          const auto index = next.findObject(edit.id);
          if (!index) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          next.removeObject(next.handleOf(*index));
          break;
        }
        case Edit::Op::Add:
          if (next.findObject(edit.object.id))
            throw EditError(i, "object.id", "duplicate object id '" + edit.object.id + "'");
          next.addObject(edit.object);
          break;
      }
    } catch (const EditError&) {
      throw;
    } catch (const std::invalid_argument& error) {
      throw EditError(i, edit.op == Edit::Op::Add ? "object" : "transform", error.what());
    }
  }
  return next;
}

// TODO(incremental): the §3 path (node deletion, casting only around the edited
// faces, relighting the dirty vertices). Until it lands, a frame rebuilds every
// DM-tree: correct, and reported as fallback rebuilds.
FrameResult Engine::apply(const Frame& frame) {
  const auto start = std::chrono::steady_clock::now();
  Scene next = sceneAfter(frame);  // throws before anything changes

  std::vector<FaceId> before;
  for (const Receiver& r : receivers_) before.push_back(r.face);
  Engine rebuilt(std::move(next), settings_);
  const uint64_t version = version_ + 1;
  *this = std::move(rebuilt);
  version_ = version;

  FrameResult result;
  result.version = version_;
  for (const Receiver& r : receivers_) {
    result.changedReceivers.push_back(r.face);
    result.verticesRelit += r.tree.vertexCount();
  }
  result.verticesChanged = result.verticesRelit;
  for (FaceId face : before)
    if (!receiver(face)) result.removedReceivers.push_back(face);
  result.treeRebuilds = receivers_.size();
  result.seconds.add = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace penumbra
