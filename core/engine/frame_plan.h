// One frame of Engine::apply (apply_frame.cpp) as the paper's phases see it: the plan (what
// leaves, what enters, whether a whole rebuild is cheaper) and the working state the remove and
// add phases (frame_remove.cpp, frame_add.cpp) hand on to relight (frame_relight.cpp).
// Plain data, internal to the engine.
#pragma once

#include <cstdint>
#include <map>
#include <set>
#include <vector>

#include "core/engine/dirty_set.h"
#include "core/geom/vec.h"
#include "core/scene/scene.h"

namespace penumbra {

struct FramePlan {
  // The frame's net effect per object handle (a move is remove + add, §3): every named object
  // that was there leaves (a no-op move is still re-cast), every one there afterwards enters.
  std::set<uint32_t> leaving, entering;
  std::vector<FaceId> leavingFaces;      // the leaving objects' faces
  std::vector<FaceId> leavingReceivers;  // those of them that had a DM-tree
  std::vector<Vec3> radianceBefore;      // each light's, when the frame changes a radiance
  std::vector<FaceId> receiversBefore;   // every receiver's face, when the frame moves a light
  // A frame undoing a large share of the cast pairs costs more than a rebuild (they are
  // undone, then redone); one reshaping the lights changes every cube, order and shadow.
  bool largeFrame = false, lightMoved = false;
  bool incremental() const { return !largeFrame && !lightMoved; }
};

// What the remove and add phases leave for the next one.
struct FrameWork {
  DirtySet dirty;                       // the relight set (§3.3)
  std::vector<bool> dropped;            // receivers_ slots whose receiver left
  std::map<FaceId, size_t> freeSlots;   // a moved face's old slot, for its new tree
  std::set<FaceId> rebuild;             // receivers whose node deletion threw: cast afresh
  std::set<FaceId> rebuiltTrees;        // receivers whose tree rebuilt itself in a deletion
  bool appendedOutOfOrder = false;      // a receiver joined past one with a larger face id
};

}  // namespace penumbra
