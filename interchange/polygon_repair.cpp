#include "interchange/polygon_repair.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "core/geom/plane_frame.h"
#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "protocol/scene_json.h"

namespace penumbra::interchange {

namespace {

// Joined pieces must be flat to rounding, so joining never bends a surface.
constexpr double kJoinPlanarity = 1e-9;

Polygon3 pointsOf(const std::vector<Vec3>& positions, const IndexPolygon& polygon) {
  Polygon3 points;
  points.reserve(polygon.size());
  for (int i : polygon) points.push_back(positions[size_t(i)]);
  return points;
}

// Ear clipping in the plane of the Newell normal; triangles wound like the input.
// Returns false when no ear can be found (a self-intersecting outline).
bool clipEars(const std::vector<Vec3>& positions, const IndexPolygon& polygon, const Vec3& normal,
              std::vector<IndexPolygon>& triangles) {
  const Polygon3 points = pointsOf(positions, polygon);
  const PlaneFrame frame = PlaneFrame::onPlane(Plane::throughPoint(normal, points[0]), points[0]);
  std::vector<Vec2> q;
  for (const Vec3& p : points) q.push_back(frame.to2D(p));
  const double size = extent(points);
  const double tiny = 1e-14 * size * size;  // twice a triangle area treated as zero

  std::vector<size_t> ring(polygon.size());
  for (size_t i = 0; i < ring.size(); ++i) ring[i] = i;
  auto turn = [&](size_t a, size_t b, size_t c) { return cross2(q[b] - q[a], q[c] - q[b]); };
  auto inside = [&](const Vec2& p, size_t a, size_t b, size_t c) {
    return cross2(q[b] - q[a], p - q[a]) >= -tiny && cross2(q[c] - q[b], p - q[b]) >= -tiny &&
           cross2(q[a] - q[c], p - q[c]) >= -tiny;
  };
  while (ring.size() > 3) {
    const size_t n = ring.size();
    bool clipped = false;
    for (size_t k = 0; k < n && !clipped; ++k) {
      const size_t a = ring[(k + n - 1) % n], b = ring[k], c = ring[(k + 1) % n];
      if (turn(a, b, c) <= tiny) continue;  // reflex or flat: not an ear
      bool empty = true;
      for (size_t m = 0; m < n && empty; ++m) {
        const size_t v = ring[m];
        if (v == a || v == b || v == c || q[v] == q[a] || q[v] == q[b] || q[v] == q[c]) continue;
        empty = !inside(q[v], a, b, c);
      }
      if (!empty) continue;
      triangles.push_back({polygon[a], polygon[b], polygon[c]});
      ring.erase(ring.begin() + std::ptrdiff_t(k));
      clipped = true;
    }
    // A flat corner (collinear or doubled-back vertex) adds no area: drop it.
    for (size_t k = 0; k < n && !clipped; ++k) {
      const size_t a = ring[(k + n - 1) % n], b = ring[k], c = ring[(k + 1) % n];
      if (std::abs(turn(a, b, c)) <= tiny) {
        ring.erase(ring.begin() + std::ptrdiff_t(k));
        clipped = true;
      }
    }
    if (!clipped) return false;
  }
  if (turn(ring[0], ring[1], ring[2]) > tiny)
    triangles.push_back({polygon[ring[0]], polygon[ring[1]], polygon[ring[2]]});
  return true;
}

// The union of two pieces across their shared edge a→b (in p) / b→a (in q).
IndexPolygon splice(const IndexPolygon& p, const IndexPolygon& q, int a, int b) {
  IndexPolygon merged;
  const size_t pn = p.size(), qn = q.size();
  const size_t pb = size_t(std::find(p.begin(), p.end(), b) - p.begin());
  for (size_t k = 0; k < pn; ++k) merged.push_back(p[(pb + k) % pn]);  // b … a
  const size_t qa = size_t(std::find(q.begin(), q.end(), a) - q.begin());
  for (size_t k = 1; k + 1 < qn; ++k) merged.push_back(q[(qa + k) % qn]);  // after a … before b
  return merged;
}

bool acceptableJoin(const std::vector<Vec3>& positions, const IndexPolygon& merged) {
  if (merged.size() > protocol::kMaxPolygonVertices) return false;
  if (std::set<int>(merged.begin(), merged.end()).size() != merged.size()) return false;
  const Polygon3 points = pointsOf(positions, merged);
  return planarityError(points) <= kJoinPlanarity && isConvex(points);
}

}  // namespace

PolygonRepair repairPolygon(const std::vector<Vec3>& positions, const IndexPolygon& polygon) {
  PolygonRepair result;
  // Drop consecutive repeats (also around the end).
  IndexPolygon distinct;
  for (int i : polygon) {
    if (!distinct.empty() && (i == distinct.back() || positions[size_t(i)] == positions[size_t(distinct.back())])) {
      ++result.repeatedVerticesRemoved;
      continue;
    }
    distinct.push_back(i);
  }
  while (distinct.size() > 1 && (distinct.front() == distinct.back() ||
                                 positions[size_t(distinct.front())] == positions[size_t(distinct.back())])) {
    distinct.pop_back();
    ++result.repeatedVerticesRemoved;
  }
  if (distinct.size() < 3) {
    result.degenerate = true;
    return result;
  }
  const Polygon3 points = pointsOf(positions, distinct);
  const auto plane = planeOf(points);
  if (!plane) {
    result.degenerate = true;
    return result;
  }
  result.nonPlanar = planarityError(points) > kRelativePlanarity;
  const bool repeatsVertex = std::set<int>(distinct.begin(), distinct.end()).size() != distinct.size();
  result.nonConvex = repeatsVertex || !isConvex(points);
  if (!result.nonPlanar && !result.nonConvex && distinct.size() <= protocol::kMaxPolygonVertices) {
    result.pieces.push_back(distinct);
    return result;
  }
  std::vector<IndexPolygon> triangles;
  if (!clipEars(positions, distinct, plane->normal, triangles)) {
    result.selfIntersecting = true;
    return result;
  }
  if (triangles.empty()) {
    result.degenerate = true;
    return result;
  }
  joinCoplanarConvex(positions, triangles);
  result.pieces = std::move(triangles);
  return result;
}

size_t joinCoplanarConvex(const std::vector<Vec3>& positions, std::vector<IndexPolygon>& pieces,
                          std::vector<size_t>* joinedInto) {
  std::map<std::pair<int, int>, size_t> owner;  // directed edge → piece
  auto forEdges = [](const IndexPolygon& p, auto&& visit) {
    for (size_t k = 0; k < p.size(); ++k) visit(p[k], p[(k + 1) % p.size()]);
  };
  for (size_t i = 0; i < pieces.size(); ++i)
    forEdges(pieces[i], [&](int a, int b) { owner.emplace(std::pair{a, b}, i); });
  std::vector<bool> alive(pieces.size(), true);
  std::vector<size_t> into(pieces.size());  // the piece each one was joined to (itself while alive)
  for (size_t i = 0; i < into.size(); ++i) into[i] = i;
  size_t joins = 0;
  for (size_t i = 0; i < pieces.size(); ++i) {
    bool joined = true;
    while (alive[i] && joined) {
      joined = false;
      const IndexPolygon p = pieces[i];
      for (size_t k = 0; k < p.size() && !joined; ++k) {
        const int a = p[k], b = p[(k + 1) % p.size()];
        const auto it = owner.find({b, a});
        if (it == owner.end() || it->second == i || !alive[it->second]) continue;
        const size_t j = it->second;
        IndexPolygon merged = splice(p, pieces[j], a, b);
        if (!acceptableJoin(positions, merged)) continue;
        auto release = [&](const IndexPolygon& piece, size_t index) {
          forEdges(piece, [&](int u, int v) {
            const auto e = owner.find({u, v});
            if (e != owner.end() && e->second == index) owner.erase(e);
          });
        };
        release(p, i);
        release(pieces[j], j);
        alive[j] = false;
        into[j] = i;
        pieces[i] = std::move(merged);
        forEdges(pieces[i], [&](int u, int v) { owner[{u, v}] = i; });
        ++joins;
        joined = true;
      }
    }
  }
  std::vector<IndexPolygon> survivors;
  std::vector<size_t> survivorIndex(pieces.size());
  for (size_t i = 0; i < pieces.size(); ++i)
    if (alive[i]) {
      survivorIndex[i] = survivors.size();
      survivors.push_back(std::move(pieces[i]));
    }
  if (joinedInto) {
    // Follow each chain of joins to the piece that survived it.
    joinedInto->resize(pieces.size());
    for (size_t i = 0; i < pieces.size(); ++i) {
      size_t k = i;
      while (into[k] != k) k = into[k];
      (*joinedInto)[i] = survivorIndex[k];
    }
  }
  pieces = std::move(survivors);
  return joins;
}

}  // namespace penumbra::interchange
