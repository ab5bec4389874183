// The boundary of a light's visible part, light minus the union of convex shadows,
// as directed segments with the visible part on their left: the light's edges where no
// shadow covers them and each shadow's edges inside the light where no other shadow
// does. Lambert's formula is a sum over boundary edges and additive along a line, so
// these segments give the visible factor without ever forming the region: the work is
// O(edges × shadows), not pieces × shadows. Owned by one thread; buffers are reused.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/illum/chain_grid.h"
#include "core/illum/shadow_chain.h"

namespace penumbra {

struct Segment2 {
  Vec2 from{0.0}, to{0.0};
};

// Where a chain edge crosses a segment's interior, at parameter t along it: moving along the
// segment, the winding number on its right (on it, for a segment not of the chain) changes
// by `delta` there.
struct WindingStep {
  double t = 0;
  int delta = 0;
};

class VisibleContour {
 public:
  // light: convex CCW. Shadow i is points[starts[i] .. starts[i+1]), convex CCW.
  // Points within eps of a line count as on it; a shadow edge along another
  // polygon's edge (adjacent faces seen from p) is decided by the edges' directions:
  // against each other the two shadows join (interior of the union), along each
  // other the lower index keeps the edge, so a shared boundary counts once.
  // With `sharedEdges` (many shadows are a mesh's faces, which share edges), each shadow edge is
  // first offered to the shadow across it (indexTwins); elsewhere that index costs more than it
  // saves (dense clutter of boxes: +30 % of the build).
  void compute(std::span<const Vec2> light, std::span<const Vec2> points,
               std::span<const uint32_t> starts, double eps, bool sharedEdges = false);

  // After compute(): also subtracts the shadows of meshes given as one chain
  // (shadow_chain.h; covered where its winding number is positive). Light and shadow
  // edge stretches are cut where chain edges cross them and kept where the winding is
  // 0; chain edges add their stretches inside the light that no convex shadow covers
  // and that have winding 0 on their right (the visible side).
  void subtractChain(std::span<const ChainEdge> chain);

  // Tests only: false walks every stretch's winding from the light's centre (what carrying
  // them along runs of chain edges must equal).
  void setCarryWindings(bool carry) { carryWindings_ = carry; }

  // The boundary of what is left (empty when the shadows cover the light).
  std::span<const Segment2> boundary() const { return boundary_; }
  // Some shadow covers part of the light: a light edge lost a stretch, or a shadow
  // edge runs inside the light.
  bool occluded() const { return occluded_; }
  // The area left (shoelace over the boundary) and the boundary's length.
  double area() const;
  double length() const;
  // Something is left: some boundary stretch is longer than eps and the area is
  // positive (stretches shorter than eps alone are crossings that nearly meet).
  bool anyLeft(double eps) const;

 private:
  // A stretch [from, to] of an edge's parameter, with its end points: where an end
  // is a crossing with another edge, the point both edges compute alike (crossing()),
  // so the boundary closes exactly where a stretch of one edge meets one of another.
  struct Interval {
    double from = 0, to = 1;
    Vec2 fromPoint{0.0}, toPoint{0.0};
  };
  // An edge and its line: signed distance normal·x − offset, positive inside (left
  // of the counter-clockwise edge).
  struct Line {
    Vec2 from{0.0}, to{0.0}, normal{0.0};
    double offset = 0;
  };
  // The stretch of edge `edge` (an index into lines_) inside the convex polygon
  // whose edges are lines_[first, first + count) (nothing if it misses it); a polygon
  // edge along it is inside when `alongInside` (same direction) or `againstInside`
  // (opposite direction) says so.
  bool clipToPolygon(size_t edge, size_t first, size_t count, bool alongInside, bool againstInside,
                     Interval& out) const;
  // Where edges e and f cross, computed on the lower-indexed one by the other's line.
  Vec2 crossing(size_t e, size_t f) const;
  // Appends the parts of `within` not covered by covered_ to the boundary, in the
  // edge's direction or reversed.
  void emitUncovered(Interval within, bool reversed);
  void addLines(std::span<const Vec2> polygon);
  void clipEdgeOfShadow(uint32_t i, size_t edge);
  // The active shadows' edges by their exact ends, into twins_ (left empty below
  // kTwinIndexFrom shadows, or without sharedEdges). Adjacent faces of a mesh project their
  // shared edge to the same two points, in opposite directions, and the shadow across it
  // usually holds it whole: a point on a model's own faces gathers a hundred such shadows, and
  // the scan in active_ order met the one across after most of the others.
  void indexTwins(bool sharedEdges);
  // The shadow with an edge from `edge`'s end to its start (exactly), or kNoShadow.
  uint32_t twinShadow(size_t edge) const;
  // The chain's winding number at x (leaving out chain edge `skip`; for x on that edge,
  // the value on its right): the winding at the light's centroid (counted once per
  // subtractChain) plus the signed crossings of the segment from there to x, which lies in
  // the light, so only the chain edges in inLight_ can cross it (those grid_ has near it).
  int windingAt(std::span<const ChainEdge> chain, const Vec2& x, size_t skip) const;
  // Narrows [t0, t1] along a→b to the part inside the convex polygon whose edge lines are
  // lines_[first, last) (strictly: no along-edge convention); false when nothing is left.
  bool insideLines(const Vec2& a, const Vec2& b, size_t first, size_t last, double& t0, double& t1) const;
  // Into cuts_ (with 0 and 1, sorted): the parameters along a→b, a stretch of the light or a
  // convex shadow, where chain edges (those in inLight_) cross it inside the light's box
  // (grid_ gives the candidates); into `steps`, where the winding on the right of a→b changes
  // strictly inside it (WindingStep); onLine set when a chain edge's end lies exactly on a→b's
  // line (not at a or b).
  void chainCrossings(std::span<const ChainEdge> chain, const Vec2& a, const Vec2& b, std::vector<WindingStep>& steps,
                      bool& onLine);

  // origin_: a point of the light that no chain edge passes within eps of (its centre if none does).
  void chooseOrigin(std::span<const ChainEdge> chain);
  // subtractChain() for a chain whose edges near the light do not run along each other
  // (else alongEachOther_ is set).
  void subtractChainOnce(std::span<const ChainEdge> chain);
  // The chain with each edge near the light split at the other edges' ends within eps of its
  // inside, merged (mergeChainEdges), into split_.
  void splitAtNearEnds(std::span<const ChainEdge> chain);
  // Whether x, at cross2(b − a, x − a) = side, lies within eps of segment a→b's inside.
  bool nearInside(const Vec2& a, const Vec2& b, const Vec2& x, double side) const;
  // What the convex contour kept (boundary_) as stretches between the chain's crossings, with
  // the winding changes along each, linked where one ends where exactly one other starts.
  void collectBoundaryStretches(std::span<const ChainEdge> chain);
  // The chain's own boundary stretches (subtractChain): per chain edge inside the light, its
  // stretches outside every convex shadow, and the winding changes along it.
  void collectChainStretches(std::span<const ChainEdge> chain);
  // What chainCrossings() records along each in-light chain edge (slots_, inside the light) for
  // the other chain edges, into groupedHits_ by slot; each pair of edges whose boxes meet taken
  // once (a sweep over x).
  void chainPairHits(std::span<const ChainEdge> chain);
  // Chain edge c against slot's chain edge e (meet(), as chainCrossings() along e): into hits_
  // and slots_[slot].onLine; alongEachOther_ set where an end of c lies within eps of e's inside.
  void pairHit(uint32_t slot, const ChainEdge& e, double nearSide, const ChainEdge& c);
  // Each stretch's winding (on a chain edge: on its right): walked from the origin for the
  // first and the last stretch of a run of segments joined end to start, carried along the
  // run in between.
  void windStretches(std::span<const ChainEdge> chain);
  // Links the chain edges that follow one another (EdgeStretches::next): the end of one is the
  // start of the other, inside the light's box, and no other chain edge starts or ends there.
  // Between a run's first and last stretches every edge then lies in the box, where
  // chainCrossings() finds every step.
  void linkRuns(std::span<const ChainEdge> chain);

  double eps_ = 0;
  bool carryWindings_ = true;
  std::vector<Segment2> boundary_;
  std::vector<Interval> covered_;
  std::vector<Line> lines_;                  // the light's edges, then each shadow's
  std::vector<uint32_t> firstLine_;          // shadow i: lines_[firstLine_[i], firstLine_[i + 1])
  std::vector<Vec2> low_, high_;             // shadows' bounding boxes
  std::vector<uint32_t> active_;             // shadows whose box meets the light's
  static constexpr uint32_t kNoShadow = 0xffffffffu;
  uint32_t lastHolder_ = kNoShadow;          // clipEdgeOfShadow(): the shadow that held the last edge whole
  static constexpr size_t kTwinIndexFrom = 8;
  struct Twin {
    uint32_t line = 0, shadow = kNoShadow;
  };
  std::vector<Twin> twins_;                  // indexTwins(): open addressing, edgeKey() of the ends
  size_t lightLines_ = 0;
  bool occluded_ = false;
  bool allCovered_ = false;                  // one convex shadow holds the whole light
  std::vector<uint32_t> inLight_;            // chain edges whose box meets the light's
  Vec2 lightLow_{0.0}, lightHigh_{0.0};      // the light's box
  ChainGrid grid_;                           // inLight_ over the light's box
  Vec2 origin_{0.0};                         // a point of the light, and the chain's winding there
  int originWinding_ = 0;
  std::vector<double> cuts_;                 // chainCrossings()
  // What collectBoundaryStretches() or collectChainStretches() finds: per segment its
  // stretches_ and steps_ (sorted by t); windStretches() sets each stretch's winding.
  struct ChainStretch {
    double from = 0, to = 0;  // parameters along the edge
    int winding = 0;
  };
  struct EdgeStretches {
    Vec2 from{0.0}, to{0.0};  // the segment: a chain edge, or a stretch of the light or a convex shadow
    uint32_t edge = 0;        // its chain edge (linkRuns)
    uint32_t skip = 0;        // the chain edge windingAt leaves out (chain.size(): none)
    uint32_t firstStretch = 0, endStretch = 0;  // stretches_[firstStretch, endStretch)
    uint32_t firstStep = 0, endStep = 0;        // steps_[firstStep, endStep)
    int32_t next = -1;                          // the edge after it in a run (an index here)
    bool walkEach = false;  // a chain corner exactly on its line: each stretch walked, no run
    bool hasPrevious = false, visited = false;
  };
  std::vector<EdgeStretches> edgeStretches_;
  std::vector<ChainStretch> stretches_;
  std::vector<WindingStep> steps_;
  std::vector<int32_t> recordOf_;  // linkRuns(): per chain edge, its index in edgeStretches_ or -1
  std::vector<uint32_t> run_;
  std::vector<Segment2> kept_;
  // collectChainStretches(): per in-light chain edge (inLight_'s order) its box, its part inside
  // the light [t0, t1] (inside: not empty), eps along it, and a chain corner exactly on its line;
  // the crossings and winding steps found along it (a cut: the other edge crosses it; delta: the
  // winding on its right steps there).
  struct SlotBox {
    Vec2 low{0.0}, high{0.0};
    double t0 = 0, t1 = 1, nearSide = 0;
    bool inside = false, onLine = false;
  };
  struct ChainHit {
    uint32_t slot = 0;
    double t = 0;
    int delta = 0;
    bool cut = false;
  };
  std::vector<SlotBox> slots_;
  std::vector<uint32_t> sweep_, hitStarts_, next_;
  std::vector<ChainHit> hits_, groupedHits_;
  // subtractChain(): chain edges running along each other were found; the boundary before the
  // chain; the chain split where they do (splitAtNearEnds()).
  bool alongEachOther_ = false;
  std::vector<Segment2> savedBoundary_;
  std::vector<ChainEdge> split_;
  std::vector<uint8_t> nearLight_;
  std::vector<std::pair<double, Vec2>> ends_;
};

}  // namespace penumbra
