#include "core/illum/chain_grid.h"

#include <cmath>
#include <limits>

namespace penumbra {

int ChainGrid::column(double x) const {
  return std::clamp(int(std::floor((x - low_.x) * perCell_.x)), 0, size_ - 1);
}

int ChainGrid::row(double y) const {
  return std::clamp(int(std::floor((y - low_.y) * perCell_.y)), 0, size_ - 1);
}

void ChainGrid::build(std::span<const ChainEdge> chain, std::span<const uint32_t> edges, const Vec2& low,
                      const Vec2& high, double eps) {
  // About one edge per cell row: a segment across the light meets ~√n cells of ~1 edge.
  size_ = std::clamp(int(std::sqrt(double(edges.size()))), 1, 64);
  low_ = low - Vec2(eps);
  cell_ = glm::max(high - low + Vec2(2 * eps), Vec2(1e-300)) / double(size_);
  perCell_ = 1.0 / cell_;
  chainSize_ = chain.size();
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
  constexpr double kNever = std::numeric_limits<double>::infinity();
  int c = column(from.x), r = row(from.y);
  const int c1 = column(to.x), r1 = row(to.y);
  const auto cell = [&](int column, int row) { return uint32_t(row * size_ + column); };
  cells_.push_back(cell(c, r));
  // A grid walk (Amanatides & Woo): next[axis] is the t where a→b crosses the next grid line
  // along that axis. Where both come at once (through a corner, or so close that rounding may
  // order them either way) both neighbours are visited, so the cells stay a superset of those
  // the segment passes; the walk ends in the cell of its end.
  const int step[2] = {c1 > c ? 1 : -1, r1 > r ? 1 : -1};
  double next[2], delta[2];
  for (int axis = 0; axis < 2; ++axis) {
    const int k = axis == 0 ? c : r;
    const bool moves = axis == 0 ? c != c1 : r != r1;
    delta[axis] = moves ? cell_[axis] / std::abs(d[axis]) : 0;
    next[axis] = moves ? (low_[axis] + (k + (step[axis] > 0 ? 1 : 0)) * cell_[axis] - a[axis]) / d[axis]
                       : kNever;
  }
  while (c != c1 || r != r1) {
    const double tie = 1e-9 * std::max(delta[0], delta[1]);
    const bool stepX = c != c1 && next[0] <= next[1] + tie;
    const bool stepY = r != r1 && (!stepX || next[1] <= next[0] + tie);
    if (stepX && stepY) cells_.push_back(cell(c + step[0], r)), cells_.push_back(cell(c, r + step[1]));
    if (stepX) c += step[0], next[0] = c == c1 ? kNever : next[0] + delta[0];
    if (stepY) r += step[1], next[1] = r == r1 ? kNever : next[1] + delta[1];
    cells_.push_back(cell(c, r));
  }
  return true;
}

}  // namespace penumbra
