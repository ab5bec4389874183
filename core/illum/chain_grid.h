// A uniform grid over the light's box holding a mesh chain's edges (shadow_chain.h), so
// the chain edges a segment inside the light may cross are found among those of the
// cells it passes, not among all of them: VisibleContour::subtractChain asks this for
// every stretch of every chain edge, which made it quadratic in the silhouette's length
// (a 6,000-face teapot's chain seen from one point has hundreds of edges). Conservative:
// an edge sits in every cell its box, widened by eps, meets, and a segment visits every
// cell it passes through (both clipped to the grid); an edge that would fill more than
// a few rows of cells is visited by every query instead. One thread; buffers reused.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/illum/shadow_chain.h"
#include "core/util/stamped_set.h"

namespace penumbra {

class ChainGrid {
 public:
  // Indexes chain[j] for j in `edges` over the box [low, high].
  void build(std::span<const ChainEdge> chain, std::span<const uint32_t> edges, const Vec2& low, const Vec2& high,
             double eps);

  // Calls visit(j) once for each indexed edge j in a cell that segment a→b passes
  // (a superset of those crossing it inside the box).
  template <class Visit>
  void forEachNear(const Vec2& a, const Vec2& b, Visit&& visit) const {
    if (a == b) return forEachAt(a, visit);
    if (!cellsAlong(a, b)) return;
    seen_.clear(chainSize_);
    auto once = [&](uint32_t j) {
      if (seen_.tryInsert(j)) visit(j);
    };
    for (uint32_t j : everywhere_) once(j);
    for (uint32_t cell : cells_)
      for (uint32_t k = starts_[cell]; k < starts_[cell + 1]; ++k) once(members_[k]);
  }

 private:
  // forEachNear(x, x): the edges of the one cell x lies in (each once there, no walk).
  template <class Visit>
  void forEachAt(const Vec2& x, Visit&& visit) const {
    const Vec2 high = low_ + cell_ * double(size_);
    if (!(x.x >= low_.x && x.x <= high.x && x.y >= low_.y && x.y <= high.y)) return;
    for (uint32_t j : everywhere_) visit(j);
    const size_t cell = size_t(row(x.y)) * size_t(size_) + size_t(column(x.x));
    for (uint32_t k = starts_[cell]; k < starts_[cell + 1]; ++k) visit(members_[k]);
  }

  // The cells segment a→b passes into cells_; false when it misses the grid.
  bool cellsAlong(const Vec2& a, const Vec2& b) const;
  int column(double x) const;
  int row(double y) const;

  int size_ = 1;  // size_ × size_ cells
  Vec2 low_{0.0}, cell_{1.0};
  Vec2 perCell_{1.0};  // 1 / cell_: a cell's column and row by multiplying (dividing was ~5 % of a model's build)
  std::vector<uint32_t> starts_, members_;  // cell c: members_[starts_[c], starts_[c + 1])
  std::vector<uint32_t> everywhere_;        // edges visited by every query
  size_t chainSize_ = 0;
  mutable StampedSet seen_;  // the chain edges this query visited
  mutable std::vector<uint32_t> cells_;
};

}  // namespace penumbra
