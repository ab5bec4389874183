#include "core/illum/chain_grid.h"

#include <cmath>

namespace penumbra {

int ChainGrid::column(double x) const {
  return std::clamp(int(std::floor((x - low_.x) / cell_.x)), 0, size_ - 1);
}

int ChainGrid::row(double y) const {
  return std::clamp(int(std::floor((y - low_.y) / cell_.y)), 0, size_ - 1);
}

void ChainGrid::build(std::span<const ChainEdge> chain, std::span<const uint32_t> edges, const Vec2& low,
                      const Vec2& high, double eps) {
  // About one edge per cell row: a segment across the light meets ~√n cells of ~1 edge.
  size_ = std::clamp(int(std::sqrt(double(edges.size()))), 1, 64);
  low_ = low - Vec2(eps);
  cell_ = glm::max(high - low + Vec2(2 * eps), Vec2(1e-300)) / double(size_);
  if (seen_.size() < chain.size()) seen_.resize(chain.size(), 0);
  struct Span {
    int c0, c1, r0, r1;
  };
  thread_local std::vector<Span> spans;
  spans.clear();
  everywhere_.clear();
  starts_.assign(size_t(size_) * size_t(size_) + 1, 0);
  for (uint32_t j : edges) {
    const Vec2 a = glm::min(chain[j].from, chain[j].to) - Vec2(eps), b = glm::max(chain[j].from, chain[j].to) + Vec2(eps);
    const Span s{column(a.x), column(b.x), row(a.y), row(b.y)};
    spans.push_back(s);
    if ((s.c1 - s.c0 + 1) * (s.r1 - s.r0 + 1) > 4 * size_) continue;
    for (int r = s.r0; r <= s.r1; ++r)
      for (int c = s.c0; c <= s.c1; ++c) ++starts_[size_t(r * size_ + c) + 1];
  }
  for (size_t c = 0; c + 1 < starts_.size(); ++c) starts_[c + 1] += starts_[c];
  members_.resize(starts_.back());
  thread_local std::vector<uint32_t> next;
  next.assign(starts_.begin(), starts_.end() - 1);
  for (size_t i = 0; i < edges.size(); ++i) {
    const Span& s = spans[i];
    if ((s.c1 - s.c0 + 1) * (s.r1 - s.r0 + 1) > 4 * size_) {
      everywhere_.push_back(edges[i]);
      continue;
    }
    for (int r = s.r0; r <= s.r1; ++r)
      for (int c = s.c0; c <= s.c1; ++c) members_[next[size_t(r * size_ + c)]++] = edges[i];
  }
}

bool ChainGrid::cellsAlong(const Vec2& a, const Vec2& b) const {
  cells_.clear();
  const Vec2 high = low_ + cell_ * double(size_), d = b - a;
  // The part of a→b inside the grid's box (t in [t0, t1]).
  double t0 = 0, t1 = 1;
  for (int axis = 0; axis < 2; ++axis) {
    if (d[axis] == 0) {
      if (a[axis] < low_[axis] || a[axis] > high[axis]) return false;
      continue;
    }
    double ta = (low_[axis] - a[axis]) / d[axis], tb = (high[axis] - a[axis]) / d[axis];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 <= t1)) return false;
  const Vec2 from = a + t0 * d, to = a + t1 * d;
  const int c0 = column(from.x), c1 = column(to.x), r0 = row(from.y), r1 = row(to.y);
  if (c0 == c1 && r0 == r1) {  // both ends in one cell (most chain edges): all of it
    cells_.push_back(uint32_t(r0 * size_ + c0));
    return true;
  }
  // Where it crosses grid lines, each axis's in increasing t, merged: between two of
  // these it stays in one cell.
  crossings_.assign({t0});
  for (int axis = 0; axis < 2; ++axis) {
    const int k0 = axis == 0 ? c0 : r0, k1 = axis == 0 ? c1 : r1;
    const size_t begin = crossings_.size();
    for (int k = std::min(k0, k1) + 1; k <= std::max(k0, k1); ++k) {
      const double t = (low_[axis] + k * cell_[axis] - a[axis]) / d[axis];
      if (t > t0 && t < t1) crossings_.push_back(t);
    }
    if (k1 < k0) std::reverse(crossings_.begin() + long(begin), crossings_.end());
    std::inplace_merge(crossings_.begin() + 1, crossings_.begin() + long(begin), crossings_.end());
  }
  crossings_.push_back(t1);
  for (size_t i = 0; i + 1 < crossings_.size(); ++i) {
    const Vec2 middle = a + (0.5 * (crossings_[i] + crossings_[i + 1])) * d;
    const uint32_t cell = uint32_t(row(middle.y) * size_ + column(middle.x));
    if (cells_.empty() || cells_.back() != cell) cells_.push_back(cell);
  }
  return true;
}

}  // namespace penumbra
