// The single DM-tree of one occluder on one receiver (paper §2.3): penumbra edges
// as a linear chain, umbra edges behind it, internal segments filtered down from
// the first umbra node. Built once per SingleShadow; plain data, thread-safe to read.
#pragma once

#include <functional>
#include <vector>

#include "core/dmtree/half_edge_mesh.h"
#include "core/geom/tolerance.h"
#include "core/shadow/single_shadow.h"

namespace penumbra {

struct SingleTreeNode {
  enum class Region : uint8_t { None, Out, Penumbra, Umbra };
  Region region = Region::None;  // a leaf iff not None
  // Internal nodes: the segment a→b on `line` (front = right of a→b = outside for
  // polygon edges) and the critical surface that generates it.
  Line2 line;
  Vec2 a{0.0}, b{0.0};
  SegmentKind kind = SegmentKind::Internal;
  ElementRef lightElement, occluderElement;
  bool generated = false;  // false: a region edge no CriticalSegment matched (e.g. on the receiver's boundary)
  int front = -1, back = -1;
};

// One discontinuity of a single tree as an inserted shadow keeps it: its ends and kind (node
// removal asks whether another occluder's segment still lies on an edge). 40 bytes, not the
// whole node's ~90: every inserted shadow keeps them as long as it stays in the tree.
struct KeptSegment {
  Vec2 a{0.0}, b{0.0};
  SegmentKind kind = SegmentKind::Internal;
};
static_assert(sizeof(KeptSegment) == 40);

struct SingleTree {
  std::vector<SingleTreeNode> nodes;
  int root = -1;  // -1: the shadow misses the receiver
  Polygon2 penumbra, umbra;  // the regions, short edges dropped
  // Every discontinuity the tree carries (region edges and internal segments).
  std::vector<KeptSegment> segments() const;
};

// `beat` (may be empty) is called every kSegmentsPerBeat internal segments filtered in: a model's
// shadow on the floor carries ten thousand (seconds); it may throw to abandon the build.
SingleTree buildSingleTree(const SingleShadow& shadow, const Tolerance& tolerance,
                           const std::function<void()>& beat = {});
constexpr size_t kSegmentsPerBeat = 256;

// A shadow region as the tree merges it: without edges of length <= eps (empty if no
// positive area is left).
Polygon2 withoutShortEdges(const Polygon2& polygon, double eps);

}  // namespace penumbra
