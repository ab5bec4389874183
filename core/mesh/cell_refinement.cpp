#include "core/mesh/cell_refinement.h"

#include "core/mesh/bucket_table.h"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>
#include <utility>

namespace penumbra {

namespace {

constexpr uint32_t kPasses = 0xffffffffu;  // an edge decided: not halved
constexpr int kMaxRounds = 40;

class Refiner {
 public:
  Refiner(PieceRefinement& piece, const RefineSettings& settings, const PointEvaluator& evaluate,
          const LevelEvaluator& level)
      : piece_(piece), settings_(settings), evaluate_(evaluate), level_(level) {}

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
    innerMeasured_ = false;  // measured once this round if a failing edge asks
    std::vector<std::array<uint32_t, 3>> mids(piece_.triangles.size());
    std::vector<uint32_t> centroids(piece_.triangles.size(), kPasses);
    bool any = false;
    settled_.resize(piece_.triangles.size(), 0);
    for (size_t t = 0; t < piece_.triangles.size(); ++t) {
      const auto& tri = piece_.triangles[t];
      mids[t] = {kPasses, kPasses, kPasses};
      if (settled_[t]) continue;  // its edges and centroid passed in an earlier round: they still do
      bool halved = false;
      for (int e = 0; e < 3; ++e) {
        mids[t][e] = decideEdge(tri[e], tri[(e + 1) % 3]);
        halved |= mids[t][e] != kPasses;
      }
      if (!halved) centroids[t] = decideCentroid(tri);
      any |= halved || centroids[t] != kPasses;
    }
    if (!any) return false;
    if (piece_.points.size() > settings_.maxPoints) {  // the round does not fit: undo it (the last)
      truncate(pointsBefore);
      piece_.capped = true;
      return false;
    }
    std::vector<std::array<uint32_t, 3>> next;
    std::vector<uint8_t> settled;
    next.reserve(piece_.triangles.size() * 3);
    for (size_t t = 0; t < piece_.triangles.size(); ++t) {
      const bool kept = mids[t] == std::array<uint32_t, 3>{kPasses, kPasses, kPasses} && centroids[t] == kPasses;
      split(piece_.points, piece_.triangles[t], mids[t], centroids[t], next);
      settled.resize(next.size(), kept ? 1 : 0);
    }
    piece_.triangles = std::move(next);
    settled_ = std::move(settled);
    return true;
  }

  // Drops the points from `count` on.
  void truncate(size_t count) {
    piece_.points.resize(count);
    piece_.values.resize(count * piece_.lights);
    piece_.levels.resize(count * piece_.lights);
  }

  // Appends the exact values at q; returns its index.
  uint32_t addPoint(const Vec2& q) {
    const size_t before = piece_.values.size();
    ++piece_.asked;
    evaluate_(q, piece_.values);
    if (piece_.values.size() != before + piece_.lights) throw std::logic_error("refinePiece: a value per light");
    piece_.points.push_back(q);
    piece_.levels.resize(piece_.values.size(), std::nan(""));
    return uint32_t(piece_.points.size() - 1);
  }

  // Point i's unshadowed level of light l: its factor where the light is wholly seen, else
  // asked of the evaluator (once per point).
  double levelOf(uint32_t i, size_t l) {
    const size_t lights = piece_.lights;
    const VertexLight& value = piece_.values[i * lights + l];
    if (value.applies() && value.lightClass() == LightClass::Lit) return value.factor();
    if (std::isnan(piece_.levels[i * lights + l])) {
      levels_.clear();
      level_(piece_.points[i], levels_);
      if (levels_.size() != lights) throw std::logic_error("refinePiece: a level per light");
      std::copy(levels_.begin(), levels_.end(), piece_.levels.begin() + long(i * lights));
    }
    return piece_.levels[i * lights + l];
  }

  // Whether the value at point m is off the mean of `from` by more than the tolerance for some
  // light, relative to the largest unshadowed level among them and m (a level is at least the
  // visible factor: below tolerance × the largest factor the test passes without levels).
  bool fails(uint32_t m, std::span<const uint32_t> from) {
    const size_t lights = piece_.lights;
    for (size_t l = 0; l < lights; ++l) {
      double mean = 0, largest = piece_.values[m * lights + l].factor();
      for (uint32_t i : from) {
        const double factor = piece_.values[i * lights + l].factor();
        mean += factor;
        largest = std::max(largest, factor);
      }
      mean /= double(from.size());
      const double error = std::abs(piece_.values[m * lights + l].factor() - mean);
      if (!(error > settings_.tolerance * largest)) continue;
      double level = levelOf(m, l);
      for (uint32_t i : from) level = std::max(level, levelOf(i, l));
      if (error > settings_.tolerance * level) return true;
    }
    return false;
  }

  // A triangle's height over its longest side (twice its area over that side's length).
  double heightOf(const std::array<uint32_t, 3>& tri) const {
    const Vec2 a = piece_.points[tri[0]], b = piece_.points[tri[1]], c = piece_.points[tri[2]];
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    return longest > 0 ? std::abs(cross2(b - a, c - a)) / longest : 0;
  }

  // For every edge two triangles of the piece share (an inner edge), the smaller of their
  // heights; edges on the piece's outline are not listed.
  void measureInteriorEdges() {
    inner_.clear();
    for (const auto& tri : piece_.triangles) {
      const double height = heightOf(tri);
      for (int e = 0; e < 3; ++e) {
        const auto [a, b] = keyOf(tri[e], tri[(e + 1) % 3]);
        auto& [count, lowest] = *inner_.tryEmplace(a, b, {0, height}).first;
        ++count, lowest = std::min(lowest, height);
      }
    }
  }

  static std::pair<uint32_t, uint32_t> keyOf(uint32_t a, uint32_t b) { return {std::min(a, b), std::max(a, b)}; }

  // The midpoint's index if edge (a, b) is halved, else kPasses; decided once per edge. An
  // edge on the piece's outline is decided by its test alone, so the piece or cell beyond it
  // decides alike. An inner edge whose test fails is still not halved while a triangle on it
  // is thinner than 2·minHeight(): halving would make it thinner still, and repeated along
  // one edge that makes slivers the mesh builder's merge within eps can fold.
  uint32_t decideEdge(uint32_t a, uint32_t b) {
    const auto key = keyOf(a, b);
    if (const uint32_t* found = edges_.find(key.first, key.second)) return *found;
    uint32_t decision = kPasses;
    const Vec2 pa = piece_.points[a], pb = piece_.points[b];
    // A refused edge is not asked its midpoint's value (2–4 % of the values asked in clutter
    // and models): whatever it is, the edge stays whole.
    if (glm::length(pb - pa) > settings_.minEdge && !tooThin(key)) {
      const uint32_t m = addPoint(0.5 * (pa + pb));  // commutative: both sides compute the same point
      const uint32_t ends[2] = {a, b};
      if (fails(m, ends)) {
        decision = m;
      } else {
        truncate(m);  // a passing midpoint is not kept
      }
    }
    edges_.tryEmplace(key.first, key.second, decision);
    return decision;
  }

  double minHeight() const { return settings_.minEdge / 16; }

  // Whether `key` is an inner edge with a triangle on it thinner than 2·minHeight().
  bool tooThin(const std::pair<uint32_t, uint32_t>& key) {
    if (!innerMeasured_) measureInteriorEdges(), innerMeasured_ = true;
    const auto* inner = inner_.find(key.first, key.second);
    return inner && inner->first == 2 && !(inner->second >= 2 * minHeight());
  }

  uint32_t decideCentroid(const std::array<uint32_t, 3>& tri) {
    const Vec2 a = piece_.points[tri[0]], b = piece_.points[tri[1]], c = piece_.points[tri[2]];
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    // A triangle too short or too thin (its height, twice its area over its longest side) is
    // not split at its centroid: repeated, that would make slivers.
    if (!(longest > settings_.minEdge) || !(heightOf(tri) > minHeight()))
      return kPasses;
    const uint32_t g = addPoint((a + b + c) / 3.0);
    if (fails(g, tri)) return g;
    truncate(g);
    return kPasses;
  }

  // Triangle (a, b, c) split by its halved edges' midpoints (mids[e] on edge e → e + 1), or
  // into three at its centroid; counter-clockwise kept.
  static void split(const std::vector<Vec2>& points, const std::array<uint32_t, 3>& tri,
                    const std::array<uint32_t, 3>& mids, uint32_t centroid, std::vector<std::array<uint32_t, 3>>& out) {
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
    // The quad (a, m0, m1, c) by its shorter diagonal (the fatter pair; ties: from m0).
    if (glm::length(points[a] - points[m1]) < glm::length(points[m0] - points[c])) {
      out.push_back({a, m0, m1});
      out.push_back({a, m1, c});
    } else {
      out.push_back({a, m0, c});
      out.push_back({m0, m1, c});
    }
  }

  PieceRefinement& piece_;
  const RefineSettings& settings_;
  const PointEvaluator& evaluate_;
  const LevelEvaluator& level_;
  BucketTable<uint32_t> edges_;  // (lower, higher index): the midpoint halving it, or kPasses
  // This round's edges: the triangles on each (2: an inner edge) and the thinner one's height.
  BucketTable<std::pair<int, double>> inner_;
  bool innerMeasured_ = false;
  std::vector<uint8_t> settled_;  // per triangle: nothing about it failed (it never will)
  std::vector<double> levels_;
};

}  // namespace

bool refinePiece(PieceRefinement& piece, const RefineSettings& settings, const PointEvaluator& evaluate,
                 const LevelEvaluator& level) {
  piece.asked = 0;
  if (!(settings.tolerance > 0) || piece.triangles.empty()) return false;
  if (piece.values.size() != piece.points.size() * piece.lights) throw std::invalid_argument("refinePiece: values");
  piece.levels.assign(piece.values.size(), std::nan(""));
  return Refiner(piece, settings, evaluate, level).run();
}

}  // namespace penumbra
