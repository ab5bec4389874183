// VisibleContour::subtractChain (visible_contour.h): a mesh's shadow given as one chain cut
// out of what the convex shadows left, each stretch kept by its winding number, walked from
// a point of the light at the ends of runs of chain edges and carried along them.
#include "core/illum/visible_contour.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

namespace {

// How chain edge c meets segment a→b: where a + t (b − a) = c.from + u (c.to − c.from) (no t
// when they are parallel), c's ends' sides of a→b's line (cross2(b − a, x − a)), whether c
// crosses a→b strictly inside it (a cut there), and the winding's step there: c crosses a→b's
// line, sides half-open as in windingAt (an end on the line counts as right of it), so a chain
// corner on the line counts once; coming from the left, c's covered (left) side lies ahead.
struct Meeting {
  double sideFrom = 0, sideTo = 0, t = 0;
  bool cut = false;
  int step = 0;
  // An end of c exactly on a→b's line but not one of its ends (a corner on it, an edge along
  // it): whether the winding steps there is what the walk's own half-open rule says.
  bool cornerOnLine = false;
};

Meeting meet(const Vec2& a, const Vec2& b, const ChainEdge& c) {
  Meeting m;
  const Vec2 d = b - a, e = c.to - c.from;
  m.sideFrom = cross2(d, c.from - a), m.sideTo = cross2(d, c.to - a);
  m.cornerOnLine = (m.sideFrom == 0 && c.from != a && c.from != b) || (m.sideTo == 0 && c.to != a && c.to != b);
  const double denominator = cross2(d, e);
  if (denominator == 0) return m;  // parallel: no single crossing
  m.t = cross2(c.from - a, e) / denominator;
  if (!(m.t > 0 && m.t < 1)) return m;
  const double u = cross2(c.from - a, d) / denominator;
  m.cut = u >= 0 && u <= 1;
  if ((m.sideFrom > 0) != (m.sideTo > 0)) m.step = m.sideFrom > 0 ? c.count : -c.count;
  return m;
}

// Steps [first, end) of `steps` in order along their segment.
void sortSteps(std::vector<WindingStep>& steps, size_t first) {
  std::sort(steps.begin() + long(first), steps.end(), [](const WindingStep& x, const WindingStep& y) { return x.t < y.t; });
}

}  // namespace

void VisibleContour::chainCrossings(std::span<const ChainEdge> chain, const Vec2& a, const Vec2& b,
                                    std::vector<WindingStep>& steps, bool& onLine) {
  cuts_.clear();
  const size_t firstStep = steps.size();
  const Vec2 low = glm::min(a, b), high = glm::max(a, b);
  grid_.forEachNear(a, b, [&](uint32_t j) {
    const ChainEdge& c = chain[j];
    if (boxesApart(low, high, glm::min(c.from, c.to), glm::max(c.from, c.to), 0)) return;
    const Meeting m = meet(a, b, c);
    onLine |= m.cornerOnLine;
    if (m.cut) cuts_.push_back(m.t);
    if (m.step != 0) steps.push_back({m.t, m.step});
  });
  cuts_.push_back(0);
  cuts_.push_back(1);
  std::sort(cuts_.begin(), cuts_.end());
  sortSteps(steps, firstStep);
}

int VisibleContour::windingAt(std::span<const ChainEdge> chain, const Vec2& x, size_t skip) const {
  const Vec2 path = x - origin_;
  double sideOfOrigin = 0;
  if (skip < chain.size()) {
    const Vec2 d = chain[skip].to - chain[skip].from;
    sideOfOrigin = cross2(d, origin_ - chain[skip].from);
    // The path runs along the edge's line, or within eps of it (past the edge's end corner,
    // where the other edges there would be counted by the rounding): count along a ray across it.
    if (std::abs(sideOfOrigin) <= eps_ * glm::length(d)) return chainWinding(chain, x, Vec2(d.y, -d.x), skip);
  }
  int w = originWinding_;
  grid_.forEachNear(origin_, x, [&](uint32_t j) {
    if (j == skip) return;
    const ChainEdge& e = chain[j];
    // Half-open on the path's line, so a path through a chain corner counts it once.
    const bool aLeft = cross2(path, e.from - origin_) > 0, bLeft = cross2(path, e.to - origin_) > 0;
    if (aLeft == bLeft) return;
    const Vec2 d = e.to - e.from;
    const double atOrigin = cross2(d, origin_ - e.from), atX = cross2(d, x - e.from);
    if ((atOrigin > 0) == (atX > 0)) return;
    w += atX > 0 ? e.count : -e.count;  // into the covered (left) side, or out of it
  });
  // Without the edge, w is the winding next to x on the origin's side: its left side
  // counts the edge's own faces too.
  if (sideOfOrigin > 0) w -= chain[skip].count;
  return w;
}

bool VisibleContour::insideLines(const Vec2& a, const Vec2& b, size_t first, size_t last, double& t0, double& t1) const {
  for (size_t k = first; k < last && t0 < t1; ++k) {
    const Line& line = lines_[k];
    if (line.normal == Vec2(0.0)) continue;
    const double dA = glm::dot(line.normal, a) - line.offset, dB = glm::dot(line.normal, b) - line.offset;
    if (dA < 0 && dB < 0) t1 = t0;
    else if (dA < 0) t0 = std::max(t0, dA / (dA - dB));
    else if (dB < 0) t1 = std::min(t1, dA / (dA - dB));
  }
  return t0 < t1;
}

bool VisibleContour::nearInside(const Vec2& a, const Vec2& b, const Vec2& x, double side) const {
  if (x == a || x == b) return false;
  const Vec2 d = b - a;
  const double length2 = glm::dot(d, d), along = glm::dot(x - a, d);
  return std::abs(side) <= eps_ * std::sqrt(length2) && along > 0 && along < length2;
}

void VisibleContour::subtractChain(std::span<const ChainEdge> chain) {
  if (chain.empty() || allCovered_) return;
  savedBoundary_.assign(boundary_.begin(), boundary_.end());
  const bool occluded = occluded_;
  alongEachOther_ = false;
  subtractChainOnce(chain);
  if (!alongEachOther_) return;
  // Chain edges run along each other near the light: each is split at the other edges' ends
  // within eps of it, so what they share becomes the same edges, which merge (summed, or
  // cancelled where they run against each other); then the chain is subtracted again.
  splitAtNearEnds(chain);
  boundary_.assign(savedBoundary_.begin(), savedBoundary_.end());
  occluded_ = occluded;
  subtractChainOnce(split_);
}

void VisibleContour::chooseOrigin(std::span<const ChainEdge> chain) {
  Vec2 centre(0.0);
  for (size_t k = 0; k < lightLines_; ++k) centre += lines_[k].from;
  centre /= double(lightLines_);
  // The light's centre, or where no chain edge passes within eps of it: a point on an edge
  // has no winding number of its own (a centre on a shadow's edge, as in a grid-aligned
  // scene). Tried towards each corner in turn, a third of the way and closer; as a last resort
  // the centre (the walks then count from a point on the chain).
  // (An edge within eps of x is in the grid's cell there: its box is widened by eps.)
  const auto clear = [&](const Vec2& x) {
    bool near = false;
    grid_.forEachNear(x, x, [&](uint32_t i) {
      const ChainEdge& c = chain[i];
      const Vec2 d = c.to - c.from;
      const double length2 = glm::dot(d, d);
      const double along = length2 > 0 ? std::clamp(glm::dot(x - c.from, d) / length2, 0.0, 1.0) : 0.0;
      near |= glm::length(x - (c.from + along * d)) <= eps_;
    });
    return !near;
  };
  origin_ = centre;
  for (int tries = 0; !clear(origin_) && tries < 4 * int(lightLines_); ++tries)
    origin_ = centre + (lines_[size_t(tries) % lightLines_].from - centre) * (1.0 / 3.0 / double(1 + tries / int(lightLines_)) + 0.0123);
  if (!clear(origin_)) origin_ = centre;
}

void VisibleContour::splitAtNearEnds(std::span<const ChainEdge> chain) {
  split_.clear();
  std::vector<uint8_t>& near = nearLight_;
  near.assign(chain.size(), 0);
  for (uint32_t i : inLight_) near[i] = 1;
  for (uint32_t i = 0; i < chain.size(); ++i) {
    const ChainEdge& c = chain[i];
    if (!near[i]) {
      split_.push_back(c);
      continue;
    }
    const Vec2 d = c.to - c.from;
    ends_.clear();
    grid_.forEachNear(c.from, c.to, [&](uint32_t j) {
      if (j == i) return;
      for (const Vec2& x : {chain[j].from, chain[j].to})
        if (nearInside(c.from, c.to, x, cross2(d, x - c.from))) ends_.push_back({glm::dot(x - c.from, d), x});
    });
    std::sort(ends_.begin(), ends_.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    Vec2 from = c.from;
    for (const auto& [along, x] : ends_) {
      if (x == from) continue;
      split_.push_back({from, x, c.count});
      from = x;
    }
    split_.push_back({from, c.to, c.count});
  }
  mergeChainEdges(split_);
}

void VisibleContour::subtractChainOnce(std::span<const ChainEdge> chain) {
  Vec2 lightLow = lines_[0].from, lightHigh = lightLow;
  for (size_t k = 0; k < lightLines_; ++k) {
    lightLow = glm::min(lightLow, lines_[k].from);
    lightHigh = glm::max(lightHigh, lines_[k].from);
  }
  lightLow_ = lightLow, lightHigh_ = lightHigh;
  inLight_.clear();
  for (uint32_t i = 0; i < chain.size(); ++i)
    if (!boxesApart(glm::min(chain[i].from, chain[i].to), glm::max(chain[i].from, chain[i].to), lightLow, lightHigh, eps_))
      inLight_.push_back(i);
  grid_.build(chain, inLight_, lightLow - Vec2(eps_), lightHigh + Vec2(eps_), eps_);
  chooseOrigin(chain);
  originWinding_ = chainWinding(chain, origin_, Vec2(0.6, 0.8), chain.size());

  // The light's and convex shadows' stretches, cut by the chain, where it covers nothing.
  collectBoundaryStretches(chain);
  windStretches(chain);
  kept_.clear();
  for (const EdgeStretches& e : edgeStretches_) {
    const Vec2 d = e.to - e.from;
    for (uint32_t k = e.firstStretch; k < e.endStretch; ++k) {
      const Vec2 from = e.from + stretches_[k].from * d, to = e.from + stretches_[k].to * d;
      if (stretches_[k].winding == 0) {
        kept_.push_back({from, to});
      } else if (glm::length(to - from) > eps_) {
        occluded_ = true;
      }
    }
  }
  boundary_.swap(kept_);

  // The chain's stretches inside the light, outside every convex shadow, visible on the right.
  collectChainStretches(chain);
  linkRuns(chain);
  windStretches(chain);
  for (const EdgeStretches& e : edgeStretches_) {
    const Vec2 d = e.to - e.from;
    for (uint32_t k = e.firstStretch; k < e.endStretch; ++k)
      if (stretches_[k].winding == 0) boundary_.push_back({e.from + stretches_[k].to * d, e.from + stretches_[k].from * d});
  }
}

void VisibleContour::pairHit(uint32_t slot, const ChainEdge& e, double nearSide, const ChainEdge& c) {
  const Meeting m = meet(e.from, e.to, c);
  slots_[slot].onLine |= m.cornerOnLine;
  // An end of c within eps of e's inside: they run along each other there (or meet in a T),
  // which the crossings cannot decide (subtractChain).
  if ((std::abs(m.sideFrom) <= nearSide && nearInside(e.from, e.to, c.from, m.sideFrom)) ||
      (std::abs(m.sideTo) <= nearSide && nearInside(e.from, e.to, c.to, m.sideTo)))
    alongEachOther_ = true;
  if (m.cut || m.step != 0) hits_.push_back({slot, m.t, m.step, m.cut});
}

void VisibleContour::chainPairHits(std::span<const ChainEdge> chain) {
  // As chainCrossings() from each in-light edge in turn (the same tests on the same numbers,
  // meet()), but each pair of edges whose boxes meet is found once, by a sweep over x, not by a walk of
  // the grid from each of them.
  hits_.clear();
  sweep_.clear();
  for (uint32_t slot = 0; slot < slots_.size(); ++slot) sweep_.push_back(slot);
  std::sort(sweep_.begin(), sweep_.end(), [&](uint32_t x, uint32_t y) { return slots_[x].low.x < slots_[y].low.x; });
  for (size_t k = 0; k < sweep_.size(); ++k) {
    const SlotBox& first = slots_[sweep_[k]];
    for (size_t m = k + 1; m < sweep_.size(); ++m) {
      const SlotBox& second = slots_[sweep_[m]];
      if (second.low.x > first.high.x) break;
      if (boxesApart(first.low, first.high, second.low, second.high, 0)) continue;
      const ChainEdge &x = chain[inLight_[sweep_[k]]], &y = chain[inLight_[sweep_[m]]];
      if (first.inside) pairHit(sweep_[k], x, first.nearSide, y);
      if (second.inside) pairHit(sweep_[m], y, second.nearSide, x);
    }
  }
  // Grouped by slot (the order within a slot does not matter: its cuts and steps are sorted).
  hitStarts_.assign(slots_.size() + 1, 0);
  for (const ChainHit& h : hits_) ++hitStarts_[h.slot + 1];
  for (size_t k = 0; k + 1 < hitStarts_.size(); ++k) hitStarts_[k + 1] += hitStarts_[k];
  groupedHits_.resize(hits_.size());
  next_.assign(hitStarts_.begin(), hitStarts_.end() - 1);
  for (const ChainHit& h : hits_) groupedHits_[next_[h.slot]++] = h;
}

void VisibleContour::collectChainStretches(std::span<const ChainEdge> chain) {
  edgeStretches_.clear();
  stretches_.clear();
  steps_.clear();
  slots_.resize(inLight_.size());
  for (uint32_t slot = 0; slot < inLight_.size(); ++slot) {
    const ChainEdge& c = chain[inLight_[slot]];
    SlotBox& box = slots_[slot];
    box.low = glm::min(c.from, c.to), box.high = glm::max(c.from, c.to);
    box.t0 = 0, box.t1 = 1;
    box.inside = insideLines(c.from, c.to, 0, lightLines_, box.t0, box.t1);
    box.nearSide = eps_ * glm::length(c.to - c.from);
    box.onLine = false;
  }
  chainPairHits(chain);
  for (uint32_t slot = 0; slot < inLight_.size(); ++slot) {
    const SlotBox& box = slots_[slot];
    if (!box.inside) continue;
    const uint32_t i = inLight_[slot];
    const ChainEdge& c = chain[i];
    const double t0 = box.t0, t1 = box.t1;
    const Vec2 d = c.to - c.from;
    occluded_ |= (t1 - t0) * glm::length(d) > eps_;
    EdgeStretches edge;
    edge.edge = edge.skip = i;
    edge.from = c.from, edge.to = c.to;
    edge.firstStep = uint32_t(steps_.size());
    cuts_.clear();
    for (uint32_t k = hitStarts_[slot]; k < hitStarts_[slot + 1]; ++k) {
      const ChainHit& h = groupedHits_[k];
      if (h.cut) cuts_.push_back(h.t);
      if (h.delta != 0) steps_.push_back({h.t, h.delta});
    }
    sortSteps(steps_, edge.firstStep);
    edge.walkEach = box.onLine;
    edge.endStep = uint32_t(steps_.size());
    // Convex shadows cover parts of it: their intervals become cuts as well.
    covered_.clear();
    for (uint32_t j : active_) {
      if (boxesApart(box.low, box.high, low_[j], high_[j], eps_)) continue;
      double u0 = 0, u1 = 1;
      if (insideLines(c.from, c.to, firstLine_[j], firstLine_[j + 1], u0, u1))
        covered_.push_back({u0, u1, c.from + u0 * d, c.from + u1 * d});
    }
    for (const Interval& cover : covered_) cuts_.insert(cuts_.end(), {cover.from, cover.to});
    cuts_.insert(cuts_.end(), {0.0, 1.0, t0, t1});
    std::sort(cuts_.begin(), cuts_.end());
    edge.firstStretch = uint32_t(stretches_.size());
    for (size_t k = 0; k + 1 < cuts_.size(); ++k) {
      const double a = cuts_[k], b = cuts_[k + 1];
      if (!(a >= t0 && b <= t1 && a < b)) continue;
      const double mid = 0.5 * (a + b);
      if (std::any_of(covered_.begin(), covered_.end(), [&](const Interval& v) { return v.from < mid && mid < v.to; }))
        continue;
      stretches_.push_back({a, b, 0});
    }
    edge.endStretch = uint32_t(stretches_.size());
    edgeStretches_.push_back(edge);
  }
}

void VisibleContour::collectBoundaryStretches(std::span<const ChainEdge> chain) {
  edgeStretches_.clear();
  stretches_.clear();
  steps_.clear();
  for (const Segment2& s : boundary_) {
    EdgeStretches edge;
    edge.skip = uint32_t(chain.size());
    edge.from = s.from, edge.to = s.to;
    edge.firstStep = uint32_t(steps_.size());
    chainCrossings(chain, s.from, s.to, steps_, edge.walkEach);
    edge.endStep = uint32_t(steps_.size());
    edge.firstStretch = uint32_t(stretches_.size());
    for (size_t k = 0; k + 1 < cuts_.size(); ++k) stretches_.push_back({cuts_[k], cuts_[k + 1], 0});
    edge.endStretch = uint32_t(stretches_.size());
    edgeStretches_.push_back(edge);
  }
  // A stretch's end that is the start of exactly one other (the light's corners, where no
  // convex shadow cuts it) carries its winding on; looked for among a few only (each pair).
  constexpr size_t kMostLinked = 64;
  for (size_t r = 0; r < edgeStretches_.size() && edgeStretches_.size() <= kMostLinked; ++r) {
    int starting = 0, ending = 0;
    size_t next = 0;
    for (size_t q = 0; q < edgeStretches_.size(); ++q) {
      if (edgeStretches_[q].from == edgeStretches_[r].to) ++starting, next = q;
      if (edgeStretches_[q].to == edgeStretches_[r].to) ++ending;
    }
    if (starting != 1 || ending != 1 || next == r || edgeStretches_[r].walkEach || edgeStretches_[next].walkEach) continue;
    edgeStretches_[r].next = int32_t(next);
    edgeStretches_[next].hasPrevious = true;
  }
}

void VisibleContour::linkRuns(std::span<const ChainEdge> chain) {
  recordOf_.assign(chain.size(), -1);
  for (size_t r = 0; r < edgeStretches_.size(); ++r) recordOf_[edgeStretches_[r].edge] = int32_t(r);
  for (size_t r = 0; r < edgeStretches_.size(); ++r) {
    EdgeStretches& e = edgeStretches_[r];
    // An end point in the light's box (widened by eps) is in the box of every chain edge
    // through it, so each of them is in inLight_ and in the grid's cell there.
    const Vec2 at = chain[e.edge].to;
    if (boxesApart(at, at, lightLow_, lightHigh_, eps_)) continue;
    int starting = 0, ending = 0;
    uint32_t next = 0;
    grid_.forEachNear(at, at, [&](uint32_t j) {
      if (chain[j].from == at) ++starting, next = j;
      if (chain[j].to == at) ++ending;
    });
    if (starting != 1 || ending != 1) continue;
    const int32_t n = recordOf_[next];
    if (n < 0 || size_t(n) == r || e.walkEach || edgeStretches_[size_t(n)].walkEach) continue;
    e.next = n;
    edgeStretches_[size_t(n)].hasPrevious = true;
  }
}

void VisibleContour::windStretches(std::span<const ChainEdge> chain) {
  const auto midpoint = [&](const EdgeStretches& e, const ChainStretch& s) {
    const Vec2 d = e.to - e.from;
    return 0.5 * (e.from + s.from * d + (e.from + s.to * d));
  };
  const auto walked = [&](uint32_t record, uint32_t k) {
    const EdgeStretches& e = edgeStretches_[record];
    return windingAt(chain, midpoint(e, stretches_[k]), e.skip);
  };
  // Runs from their first edge, then the closed ones (every edge has a previous one).
  for (int pass = 0; pass < 2; ++pass)
    for (uint32_t r = 0; r < edgeStretches_.size(); ++r) {
      if (edgeStretches_[r].visited || (pass == 0 && edgeStretches_[r].hasPrevious)) continue;
      run_.clear();
      for (int32_t at = int32_t(r); at >= 0 && !edgeStretches_[size_t(at)].visited; at = edgeStretches_[size_t(at)].next) {
        edgeStretches_[size_t(at)].visited = true;
        run_.push_back(uint32_t(at));
      }
      // The winding on the right at each stretch: walked at the run's first stretch longer
      // than eps, then carried across the steps. A stretch no longer than eps (an edge's end
      // on the light's boundary, where the walk's answer is the rounding's) is walked on its
      // own, and so is every stretch of a segment with a chain corner exactly on its line. Where the walk at the last long stretch disagrees (a chain corner exactly on an
      // edge of the run leaves a step uncounted), every stretch of the run is walked.
      bool started = false;
      int winding = 0;
      uint32_t firstStretch = 0, lastRecord = 0, lastStretch = 0;
      for (uint32_t record : run_) {
        const EdgeStretches& e = edgeStretches_[record];
        const double length = glm::length(e.to - e.from);
        uint32_t step = e.firstStep;
        for (uint32_t k = e.firstStretch; k < e.endStretch; ++k) {
          ChainStretch& s = stretches_[k];
          const double mid = 0.5 * (s.from + s.to);
          for (; step < e.endStep && steps_[step].t < mid; ++step) winding += steps_[step].delta;
          if (e.walkEach || !carryWindings_ || !((s.to - s.from) * length > eps_)) {
            s.winding = walked(record, k);
            continue;
          }
          if (!started) winding = walked(record, k), started = true, firstStretch = k;
          s.winding = winding;
          lastRecord = record, lastStretch = k;
        }
        for (; step < e.endStep; ++step) winding += steps_[step].delta;
      }
      if (!started || lastStretch == firstStretch) continue;
      if (walked(lastRecord, lastStretch) == stretches_[lastStretch].winding) continue;
      for (uint32_t record : run_)
        for (uint32_t k = edgeStretches_[record].firstStretch; k < edgeStretches_[record].endStretch; ++k)
          stretches_[k].winding = walked(record, k);
    }
}

}  // namespace penumbra
