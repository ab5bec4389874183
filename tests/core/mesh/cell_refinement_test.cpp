// refinePiece (core/mesh/cell_refinement.h) on seeded random quads with collinear side points and
// a smooth step (a penumbra's profile) as the "exact" value: a linear value adds nothing; a
// refined piece's triangles are counter-clockwise and tile the piece; every final edge passes its
// test or is at the shape limit; the point cap stops a round before it is passed and says so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <random>

#include "core/mesh/cell_refinement.h"
#include "core/mesh/cell_triangulation.h"

namespace penumbra {
namespace {

struct Step {
  Vec2 centre{0.0}, direction{1.0, 0.0};
  double width = 0.1, slope = 0;  // slope: a linear value instead
  VertexLight operator()(const Vec2& q) const {
    VertexLight v;
    v.setApplies(true);
    v.setLightClass(LightClass::Penumbra);
    const double d = glm::dot(q - centre, direction);
    v.setFactor(slope != 0 ? 1 + slope * d : 1 / (1 + std::exp(-d / width)));
    return v;
  }
};

PieceRefinement quad(double w, double h, const Step& f) {
  PieceRefinement r;
  r.lights = 1;
  r.points = {{0, 0}, {w / 3, 0}, {w, 0}, {w, h / 2}, {w, h}, {0, h}};
  for (const Vec2& q : r.points) r.values.push_back(f(q));
  const CellFan fan = fanOfConvexCell(r.points, 1e-12);
  const uint32_t n = uint32_t(r.points.size());
  if (fan.usesCentre()) {
    Vec2 c(0.0);
    for (const Vec2& q : r.points) c += q;
    r.points.push_back(c / double(n));
    r.values.push_back(f(r.points.back()));
  }
  for (uint32_t t = 0; t < fan.triangleCount(n); ++t) r.triangles.push_back(fan.triangle(n, t));
  return r;
}

bool refine(PieceRefinement& r, const RefineSettings& s, const Step& f) {
  return refinePiece(
      r, s, [&](const Vec2& q, std::vector<VertexLight>& out) { out.push_back(f(q)); },
      [](const Vec2&, std::vector<double>& out) { out.push_back(1.0); });
}

TEST(CellRefinement, LinearValueAddsNothing) {
  Step f;
  f.slope = 0.7;
  PieceRefinement r = quad(1, 0.5, f);
  const size_t before = r.points.size();
  EXPECT_FALSE(refine(r, RefineSettings{0.005, 1e-3, 1024}, f));
  EXPECT_EQ(r.points.size(), before);
}

// Seeded random quads and steps, refined; `check` sees each (piece, step).
template <typename Check>
void forRandomPieces(const RefineSettings& s, int trials, Check check) {
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < trials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    const double w = 0.05 + u(rng), h = 0.05 + u(rng), angle = 2 * M_PI * u(rng);
    Step f;
    f.centre = Vec2(u(rng) * w, u(rng) * h);
    f.direction = Vec2(std::cos(angle), std::sin(angle));
    f.width = 0.01 + 0.3 * u(rng);
    PieceRefinement r = quad(w, h, f);
    refine(r, s, f);
    check(r, f, w * h);
    if (::testing::Test::HasFailure()) return;
  }
}

constexpr RefineSettings kSettings{0.005, 2e-3, 1024};

TEST(CellRefinement, RefinedTrianglesTileThePiece) {
  forRandomPieces(kSettings, 200, [](const PieceRefinement& r, const Step&, double pieceArea) {
    double area = 0;
    for (const auto& t : r.triangles) {
      const Vec2 a = r.points[t[0]], b = r.points[t[1]], c = r.points[t[2]];
      const double twice = cross2(b - a, c - a);
      EXPECT_GT(twice, 0);
      area += twice / 2;
    }
    EXPECT_NEAR(area, pieceArea, 1e-12 * pieceArea);
  });
}

double heightOf(const PieceRefinement& r, const std::array<uint32_t, 3>& t) {
  const Vec2 a = r.points[t[0]], b = r.points[t[1]], c = r.points[t[2]];
  const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  return std::abs(cross2(b - a, c - a)) / longest;
}

// Every final edge passes its test, is too short to halve, or is an inner edge with a
// triangle on it thinner than 2·minEdge/16 (the refinement's shape limit); the quads' own
// triangles are at least 0.14·minEdge high, so the limit leaves nothing near a sliver.
TEST(CellRefinement, EveryFinalEdgePassesOrIsAtTheShapeLimit) {
  const double minHeight = kSettings.minEdge / 16;
  size_t refused = 0, edges = 0;
  double thinnest = 1e300;
  forRandomPieces(kSettings, 200, [&](const PieceRefinement& r, const Step& f, double) {
    if (r.capped) return;
    std::map<std::pair<uint32_t, uint32_t>, std::vector<double>> heights;
    for (const auto& t : r.triangles) {
      thinnest = std::min(thinnest, heightOf(r, t));
      for (int e = 0; e < 3; ++e)
        heights[{std::min(t[e], t[(e + 1) % 3]), std::max(t[e], t[(e + 1) % 3])}].push_back(heightOf(r, t));
    }
    for (const auto& [key, on] : heights) {
      const Vec2 p = r.points[key.first], q = r.points[key.second];
      if (!(glm::length(q - p) > kSettings.minEdge)) continue;
      ++edges;
      const double mean = (f(p).factor() + f(q).factor()) / 2;
      if (std::abs(f(0.5 * (p + q)).factor() - mean) <= kSettings.tolerance) continue;
      ++refused;
      EXPECT_EQ(on.size(), 2u) << "an outline edge failing its test";
      EXPECT_LT(*std::min_element(on.begin(), on.end()), 2 * minHeight);
    }
  });
  std::printf("%zu of %zu edges left at the shape limit; thinnest triangle %.3g minEdge\n", refused, edges,
              thinnest / kSettings.minEdge);
  EXPECT_GT(thinnest, 0.01 * kSettings.minEdge);
}

TEST(CellRefinement, PointCapStopsBeforeItAndSaysSo) {
  Step f;
  f.width = 0.001;
  f.centre = Vec2(0.5, 0.25);
  PieceRefinement r = quad(1, 0.5, f);
  refine(r, RefineSettings{0.005, 1e-6, 40}, f);
  EXPECT_TRUE(r.capped);
  EXPECT_LE(r.points.size(), 40u);
}

}  // namespace
}  // namespace penumbra
