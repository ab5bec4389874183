#include "core/mesh/cell_refinement.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace penumbra {

namespace {

constexpr uint32_t kPasses = 0xffffffffu;  // an edge decided: not halved
constexpr int kMaxRounds = 40;

class Refiner {
 public:
  Refiner(PieceRefinement& piece, const RefineSettings& settings, const PointEvaluator& evaluate)
      : piece_(piece), settings_(settings), evaluate_(evaluate) {}

  bool run() {
    const size_t before = piece_.points.size();
    for (int round = 0; round < kMaxRounds; ++round)
      if (!refineOnce()) break;
    return piece_.points.size() > before;
  }

 private:
  // One round; false when nothing changed.
  bool refineOnce() {
    // Decide every edge first (the same decision for both triangles on it), then the
    // centroids of triangles with no halved edge; added points are only tentative until the
    // round is known to fit maxPoints.
    const size_t pointsBefore = piece_.points.size();
    std::vector<std::array<uint32_t, 3>> mids(piece_.triangles.size());
    std::vector<uint32_t> centroids(piece_.triangles.size(), kPasses);
    bool any = false;
    for (size_t t = 0; t < piece_.triangles.size(); ++t) {
      const auto& tri = piece_.triangles[t];
      bool halved = false;
      for (int e = 0; e < 3; ++e) {
        mids[t][e] = decideEdge(tri[e], tri[(e + 1) % 3]);
        halved |= mids[t][e] != kPasses;
      }
      if (!halved) centroids[t] = decideCentroid(tri);
      any |= halved || centroids[t] != kPasses;
    }
    if (!any) return false;
    if (piece_.points.size() > settings_.maxPoints) {  // the round does not fit: undo it
      truncate(pointsBefore, true);
      piece_.capped = true;
      return false;
    }
    std::vector<std::array<uint32_t, 3>> next;
    next.reserve(piece_.triangles.size() * 3);
    for (size_t t = 0; t < piece_.triangles.size(); ++t) split(piece_.triangles[t], mids[t], centroids[t], next);
    piece_.triangles = std::move(next);
    return true;
  }

  // Drops the points from `count` on (no edge decision refers to them unless `decided`).
  void truncate(size_t count, bool decided = false) {
    piece_.points.resize(count);
    piece_.values.resize(count * piece_.lights);
    piece_.levels.resize(count * piece_.lights);
    if (decided)
      for (auto it = edges_.begin(); it != edges_.end();)
        it = it->second != kPasses && it->second >= count ? edges_.erase(it) : std::next(it);
  }

  // Appends the exact values at q; returns its index.
  uint32_t addPoint(const Vec2& q) {
    values_.clear(), levels_.clear();
    evaluate_(q, values_, levels_);
    piece_.points.push_back(q);
    piece_.values.insert(piece_.values.end(), values_.begin(), values_.end());
    piece_.levels.insert(piece_.levels.end(), levels_.begin(), levels_.end());
    return uint32_t(piece_.points.size() - 1);
  }

  // Whether the value at point m is off the weighted mean of `from` by more than the
  // tolerance for some light (relative to the largest unshadowed level among them and m).
  bool fails(uint32_t m, std::span<const uint32_t> from) const {
    const size_t lights = piece_.lights;
    for (size_t l = 0; l < lights; ++l) {
      double mean = 0, level = piece_.levels[m * lights + l];
      for (uint32_t i : from) {
        mean += piece_.values[i * lights + l].factor;
        level = std::max(level, piece_.levels[i * lights + l]);
      }
      mean /= double(from.size());
      if (std::abs(piece_.values[m * lights + l].factor - mean) > settings_.tolerance * level) return true;
    }
    return false;
  }

  // The midpoint's index if edge (a, b) is halved, else kPasses; decided once per edge.
  uint32_t decideEdge(uint32_t a, uint32_t b) {
    const std::pair<uint32_t, uint32_t> key{std::min(a, b), std::max(a, b)};
    if (const auto found = edges_.find(key); found != edges_.end()) return found->second;
    uint32_t decision = kPasses;
    const Vec2 pa = piece_.points[a], pb = piece_.points[b];
    if (glm::length(pb - pa) > settings_.minEdge) {
      const uint32_t m = addPoint(0.5 * (pa + pb));  // commutative: both sides compute the same point
      const uint32_t ends[2] = {a, b};
      if (fails(m, ends)) {
        decision = m;
      } else {
        truncate(m);  // a passing midpoint is not kept
      }
    }
    edges_[key] = decision;
    return decision;
  }

  uint32_t decideCentroid(const std::array<uint32_t, 3>& tri) {
    const Vec2 a = piece_.points[tri[0]], b = piece_.points[tri[1]], c = piece_.points[tri[2]];
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    if (!(longest > settings_.minEdge)) return kPasses;
    const uint32_t g = addPoint((a + b + c) / 3.0);
    if (fails(g, tri)) return g;
    truncate(g);
    return kPasses;
  }

  // Triangle (a, b, c) split by its halved edges' midpoints (mids[e] on edge e → e + 1), or
  // into three at its centroid; counter-clockwise kept.
  static void split(const std::array<uint32_t, 3>& tri, const std::array<uint32_t, 3>& mids, uint32_t centroid,
                    std::vector<std::array<uint32_t, 3>>& out) {
    int halved = 0;
    for (uint32_t m : mids) halved += m != kPasses ? 1 : 0;
    if (halved == 0) {
      if (centroid == kPasses) return out.push_back(tri);
      for (int e = 0; e < 3; ++e) out.push_back({tri[e], tri[(e + 1) % 3], centroid});
      return;
    }
    if (halved == 3) {
      out.push_back({tri[0], mids[0], mids[2]});
      out.push_back({mids[0], tri[1], mids[1]});
      out.push_back({mids[2], mids[1], tri[2]});
      out.push_back({mids[0], mids[1], mids[2]});
      return;
    }
    // Rotate so the pattern starts at edge 0: one halved edge (0), or two (0 and 1).
    int r = 0;
    for (; r < 3; ++r) {
      const bool first = mids[r] != kPasses, second = mids[(r + 1) % 3] != kPasses;
      if (halved == 1 ? first : first && second) break;
    }
    const uint32_t a = tri[r], b = tri[(r + 1) % 3], c = tri[(r + 2) % 3];
    const uint32_t m0 = mids[r], m1 = mids[(r + 1) % 3];
    if (halved == 1) {
      out.push_back({a, m0, c});
      out.push_back({m0, b, c});
      return;
    }
    out.push_back({m0, b, m1});
    // The quad (a, m0, m1, c) by its diagonal from m0 (the rule needs no lengths: deterministic).
    out.push_back({a, m0, c});
    out.push_back({m0, m1, c});
  }

  PieceRefinement& piece_;
  const RefineSettings& settings_;
  const PointEvaluator& evaluate_;
  std::map<std::pair<uint32_t, uint32_t>, uint32_t> edges_;
  std::vector<VertexLight> values_;
  std::vector<double> levels_;
};

}  // namespace

bool refinePiece(PieceRefinement& piece, const RefineSettings& settings, const PointEvaluator& evaluate) {
  if (!(settings.tolerance > 0) || piece.triangles.empty()) return false;
  return Refiner(piece, settings, evaluate).run();
}

}  // namespace penumbra
