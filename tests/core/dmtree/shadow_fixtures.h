// Test fixtures for the DM-tree tests: seeded random convex shadows on a receiver and
// brute-force oracles (lists by centroid, segment coverage, locate, cellsAround).
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "core/dmtree/dm_tree.h"
#include "core/geom/convex2d.h"

namespace penumbra::dmtree_test {

using Rng = std::mt19937_64;
inline const Tolerance kTol = Tolerance::forSize(2.0);

inline double uniform(Rng& rng, double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }

inline Polygon2 randomConvex(Rng& rng, Vec2 center, double radius, int count) {
  std::vector<double> angles(count);
  for (double& a : angles) a = uniform(rng, 0, 2 * M_PI);
  std::sort(angles.begin(), angles.end());
  Polygon2 out;
  const double squash = uniform(rng, 0.5, 1.0);
  for (double a : angles) out.push_back(center + radius * Vec2{std::cos(a), squash * std::sin(a)});
  return out;
}

inline Polygon2 rect(double x0, double y0, double x1, double y1) { return {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}; }

inline bool inside(const Polygon2& poly, const Vec2& p) {
  if (poly.size() < 3) return false;
  for (size_t i = 0; i < poly.size(); ++i)
    if (!(lineDistance(poly[i], poly[(i + 1) % poly.size()], p) > 0)) return false;
  return true;
}

// The area centroid (core/geom).
inline Vec2 centroidOf(const Polygon2& poly) { return areaCentroid(poly); }

// Where a ray from p (inside or on a convex CCW polygon) leaves it.
inline Vec2 rayExit(const Polygon2& poly, Vec2 p, Vec2 dir) {
  double best = INFINITY;
  for (size_t i = 0; i < poly.size(); ++i) {
    const Vec2 a = poly[i], e = poly[(i + 1) % poly.size()] - a;
    const double den = cross2(dir, e);
    if (std::abs(den) < 1e-300) continue;
    const double t = cross2(a - p, e) / den, u = cross2(a - p, dir) / den;
    if (t > 1e-12 && u >= -1e-12 && u <= 1 + 1e-12) best = std::min(best, t);
  }
  return p + best * dir;
}

inline void addRegionSegments(SingleShadow& s, const Polygon2& poly, SegmentKind kind) {
  for (size_t i = 0; i < poly.size(); ++i) {
    CriticalSegment seg;
    seg.a = poly[i];
    seg.b = poly[(i + 1) % poly.size()];
    seg.kind = kind;
    seg.lightElement = {ElementRef::Kind::Vertex, uint32_t(i % 4)};
    seg.occluderElement = {ElementRef::Kind::Edge, uint32_t(i)};
    s.segments.push_back(seg);
  }
}

inline SingleShadow randomShadow(Rng& rng, const Polygon2& receiver, uint32_t id) {
  SingleShadow s;
  s.light = 0;
  s.occluder = FaceId{id, 0};
  s.cullsBehind = true;  // an occluder clear of the receiver: its umbra culls
  for (;;) {
    const Vec2 c{uniform(rng, -1.1, 1.1), uniform(rng, -1.1, 1.1)};
    s.penumbra = intersect(randomConvex(rng, c, uniform(rng, 0.15, 0.8), 3 + int(rng() % 6)), receiver,
                           kTol.length());
    if (s.penumbra.size() >= 3 && signedArea(s.penumbra) > 1e-4) break;
  }
  const Vec2 pc = centroidOf(s.penumbra);
  if (rng() % 10 < 7) {
    Polygon2 u = randomConvex(rng, pc, uniform(rng, 0.05, 0.4), 3 + int(rng() % 5));
    s.umbra = intersect(u, s.penumbra, kTol.length());
    if (s.umbra.size() < 3 || signedArea(s.umbra) < 1e-5) s.umbra.clear();
  }
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  addRegionSegments(s, s.umbra, SegmentKind::Umbra);
  const int internal = int(rng() % 4);
  for (int k = 0; k < internal; ++k) {
    CriticalSegment seg;
    seg.kind = SegmentKind::Internal;
    seg.lightElement = {ElementRef::Kind::Edge, uint32_t(k)};
    seg.occluderElement = {ElementRef::Kind::Vertex, uint32_t(k)};
    if (!s.umbra.empty()) {
      // EV-like: from the umbra boundary outwards to the penumbra boundary.
      const size_t i = rng() % s.umbra.size();
      const Vec2 a = s.umbra[i], b = s.umbra[(i + 1) % s.umbra.size()];
      const Vec2 p = a + uniform(rng, 0.1, 0.9) * (b - a);
      const Vec2 e = glm::normalize(b - a), n{e.y, -e.x};
      const double turn = uniform(rng, -0.7, 0.7);
      const Vec2 dir = std::cos(turn) * n + std::sin(turn) * e;
      seg.a = p;
      seg.b = rayExit(s.penumbra, p, dir);
    } else {
      const Vec2 p = pc + 0.5 * uniform(rng, 0, 1) * (s.penumbra[rng() % s.penumbra.size()] - pc);
      const double angle = uniform(rng, 0, 2 * M_PI);
      seg.a = p;
      seg.b = rayExit(s.penumbra, p, {std::cos(angle), std::sin(angle)});
    }
    if (std::isfinite(seg.b.x) && std::isfinite(seg.b.y) && glm::length(seg.b - seg.a) > 1e-6)
      s.segments.push_back(seg);
  }
  return s;
}

inline double pointSegmentDistance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 d = b - a;
  const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(p - (a + t * d));
}

// Whether the cell holding p lists an umbra entry (light 0, the fixtures' light).
inline bool inUmbraAt(const DmTree& tree, const Vec2& p) { return hasUmbraEntry(tree.occluders(tree.locate(p)), 0); }

// Every shadow's discontinuities lie on mesh edges (sampled), or, with umbra culling
// (DmTree's default), inside a cell in the light's umbra, where they were culled.
inline void expectCovered(const DmTree& tree, const SingleShadow& s, bool culling = true) {
  const HalfEdgeMesh& mesh = tree.mesh();
  for (const CriticalSegment& seg : s.segments)
    for (int k = 0; k < 5; ++k) {
      const Vec2 p = seg.a + (k + 0.5) / 5.0 * (seg.b - seg.a);
      bool covered = false;
      for (uint32_t i = 0; i < mesh.halfEdgeSlots() && !covered; i += 2) {
        const HalfEdgeId h(i);
        if (!mesh.halfEdge(h).alive()) continue;
        covered = pointSegmentDistance(p, mesh.vertex(mesh.halfEdge(h).origin).position,
                                       mesh.vertex(mesh.destination(h)).position) <= kTol.length();
      }
      if (!covered && culling && inUmbraAt(tree, p)) continue;
      ASSERT_TRUE(covered) << "segment point (" << p.x << ", " << p.y << ") not on any edge";
    }
}

// Lists by brute force: a shadow covers a cell iff its penumbra holds the centroid.
// With umbra culling (DmTree's default) a cell in an umbra lists some of the shadows
// covering it (those inserted before it was in umbra), with their right flags, and at
// least one umbra entry; a cell in no umbra lists every one.
inline void expectLists(const DmTree& tree, const std::vector<SingleShadow>& shadows, bool culling = true) {
  for (CellId c : tree.cells()) {
    const Vec2 p = centroidOf(tree.cellPolygon(c));
    std::set<std::pair<uint32_t, bool>> expected, actual;
    for (const SingleShadow& s : shadows)
      if (inside(s.penumbra, p)) expected.insert({s.occluder.object, inside(s.umbra, p)});
    for (const OccluderEntry& e : tree.occluders(c)) actual.insert({e.face.object, e.umbra});
    const auto umbra = [](const std::set<std::pair<uint32_t, bool>>& list) {
      return std::any_of(list.begin(), list.end(), [](const auto& e) { return e.second; });
    };
    if (!culling || !umbra(expected)) {
      ASSERT_EQ(actual, expected) << "cell " << c.index;
      continue;
    }
    ASSERT_TRUE(umbra(actual)) << "cell " << c.index << " in an umbra lists none";
    ASSERT_TRUE(std::includes(expected.begin(), expected.end(), actual.begin(), actual.end()))
        << "cell " << c.index << " lists a shadow that does not cover it";
  }
}

inline void expectQueries(const DmTree& tree) {
  const std::vector<CellId> cells = tree.cells();
  std::vector<Polygon2> polys;
  for (CellId c : cells) {
    polys.push_back(tree.cellPolygon(c));
    ASSERT_EQ(tree.locate(centroidOf(polys.back())), c);
  }
  for (VertexId v : tree.vertices()) {
    std::vector<CellId> around = tree.cellsAround(v);
    std::sort(around.begin(), around.end());
    std::vector<CellId> brute;
    for (size_t i = 0; i < cells.size(); ++i)
      if (contains(polys[i], tree.position(v), kTol.length())) brute.push_back(cells[i]);
    ASSERT_EQ(around, brute) << "vertex " << v.index;
  }
}

}  // namespace penumbra::dmtree_test
