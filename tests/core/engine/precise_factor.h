// Test-only: a third, independent value in extended precision (long double) for
// the visible part of a light: the light clipped to p's front, minus the central
// projections of every face p lies more than onPlane() behind (SCENE_FORMAT.md
// blocking rule), then Lambert's formula. Uses neither core/illum nor
// core/reference and no snapping tolerance at all, so it decides who is right
// where the engine's backprojection and the brute-force reference disagree.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {
namespace precise {

using LD = long double;
struct V3 {
  LD x = 0, y = 0, z = 0;
};
inline V3 operator+(V3 a, V3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline V3 operator-(V3 a, V3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline V3 operator*(V3 a, LD s) { return {a.x * s, a.y * s, a.z * s}; }
inline LD dot(V3 a, V3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline V3 cross(V3 a, V3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
inline LD norm(V3 a) { return std::sqrt(dot(a, a)); }
inline V3 wide(const Vec3& v) { return {v.x, v.y, v.z}; }
struct V2 {
  LD x = 0, y = 0;
};
using P2 = std::vector<V2>;
using P3 = std::vector<V3>;

inline V3 newell(const P3& poly) {
  V3 n;
  for (size_t i = 0; i < poly.size(); ++i) {
    const V3 a = poly[i], b = poly[(i + 1) % poly.size()];
    n.x += (a.y - b.y) * (a.z + b.z);
    n.y += (a.z - b.z) * (a.x + b.x);
    n.z += (a.x - b.x) * (a.y + b.y);
  }
  return n;
}

// The part of a convex polygon where f > 0 (boundary points kept); no tolerance.
template <typename T, typename F>
std::vector<T> keep(const std::vector<T>& poly, F f) {
  std::vector<T> out;
  const size_t n = poly.size();
  for (size_t i = 0; i < n; ++i) {
    const T a = poly[i], b = poly[(i + 1) % n];
    const LD da = f(a), db = f(b);
    if (da >= 0) out.push_back(a);
    if ((da > 0 && db < 0) || (da < 0 && db > 0)) {
      const LD t = da / (da - db);
      if constexpr (std::is_same_v<T, V3>) out.push_back(a + (b - a) * t);
      else out.push_back(V2{a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t});
    }
  }
  return out.size() >= 3 ? out : std::vector<T>{};
}

inline LD area(const P2& p) {
  LD s = 0;
  for (size_t i = 1; i + 1 < p.size(); ++i)
    s += (p[i].x - p[0].x) * (p[i + 1].y - p[0].y) - (p[i].y - p[0].y) * (p[i + 1].x - p[0].x);
  return s / 2;
}

inline LD lambert(V3 p, V3 n, const P3& poly) {
  LD sum = 0;
  for (size_t i = 0; i < poly.size(); ++i) {
    const V3 a = poly[i] - p, b = poly[(i + 1) % poly.size()] - p;
    const V3 c = cross(a, b);
    const LD s = norm(c);
    if (s > 0) sum += std::atan2(s, dot(a, b)) * dot(n, c) / s;
  }
  return std::abs(sum) / 2;
}

// The visible factor of light l from p (0 if the light does not face p).
inline LD preciseFactor(const Scene& scene, size_t l, const Vec3& pd, const Vec3& nd) {
  const V3 p = wide(pd), n = wide(nd);
  P3 light;
  for (const Vec3& q : scene.lights()[l].polygon) light.push_back(wide(q));
  V3 ln = newell(light);
  ln = ln * (1 / norm(ln));
  const LD offset = -dot(ln, light[0]);
  auto height = [&](V3 x) { return dot(ln, x) + offset; };
  const LD pHeight = height(p);
  if (!(pHeight > 0)) return 0;
  const P3 front = keep(light, [&](V3 v) { return dot(n, v - p); });
  if (front.empty()) return 0;
  V3 u = cross(std::abs(ln.x) < 0.5 ? V3{1, 0, 0} : V3{0, 1, 0}, ln);
  u = u * (1 / norm(u));
  const V3 w = cross(ln, u), o = light[0];
  auto to2 = [&](V3 q) { return V2{dot(q - o, u), dot(q - o, w)}; };
  auto to3 = [&](V2 q) { return o + u * q.x + w * q.y; };
  P2 front2;
  for (V3 q : front) front2.push_back(to2(q));
  if (area(front2) < 0) std::reverse(front2.begin(), front2.end());

  // The cone from p over the front part scaled 3× about its vertex centroid: it
  // keeps the projections bounded (a blocker point at nearly p's height outside it
  // would land ~1e12 away and ruin the 2D arithmetic); all it removes projects
  // outside the light.
  V3 mid;
  for (V3 q : front) mid = mid + q * (LD(1) / front.size());
  std::vector<V3> cone;  // inward normals of planes through p
  for (size_t i = 0; i < front.size(); ++i) {
    const V3 a = mid + (front[i] - mid) * 3, b = mid + (front[(i + 1) % front.size()] - mid) * 3;
    V3 normal = cross(a - p, b - p);
    if (dot(normal, mid - p) < 0) normal = normal * -1;
    if (norm(normal) > 0) cone.push_back(normal);
  }

  std::vector<P2> pieces{front2};
  const double onPlane = scene.tolerance().onPlane();
  for (const Face& face : scene.faces()) {
    if (!(face.plane.signedDistance(pd) < -onPlane)) continue;
    P3 blocker;
    for (const Vec3& v : face.polygon) blocker.push_back(wide(v));
    // Strictly between the light's plane and p's height (a blocking face is
    // onPlane() from p, so the cap just short of p's height removes nothing that
    // projects onto the light).
    blocker = keep(blocker, height);
    blocker = keep(blocker, [&](V3 v) { return pHeight * (1 - 1e-12L) - height(v); });
    for (V3 side : cone)
      if (!blocker.empty()) blocker = keep(blocker, [&](V3 v) { return dot(side, v - p); });
    if (blocker.empty()) continue;
    P2 shadow;
    for (V3 x : blocker) shadow.push_back(to2(p + (x - p) * (pHeight / (pHeight - height(x)))));
    if (area(shadow) < 0) std::reverse(shadow.begin(), shadow.end());
    if (!(area(shadow) > 0)) continue;
    std::vector<P2> next;
    for (const P2& piece : pieces) {
      std::vector<P2> outside;
      P2 rest = piece;
      for (size_t i = 0; i < shadow.size() && !rest.empty(); ++i) {
        const V2 a = shadow[i], b = shadow[(i + 1) % shadow.size()];
        auto left = [&](V2 q) { return (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x); };
        P2 right = keep(rest, [&](V2 q) { return -left(q); });
        if (!right.empty()) outside.push_back(std::move(right));
        rest = keep(rest, left);
      }
      if (rest.empty() || !(area(rest) > 0)) {
        next.push_back(piece);  // no overlap: the piece stays whole
      } else {
        for (P2& part : outside) next.push_back(std::move(part));
      }
    }
    pieces = std::move(next);
  }
  LD sum = 0;
  for (const P2& piece : pieces) {
    P3 world;
    for (V2 q : piece) world.push_back(to3(q));
    sum += lambert(p, n, world);
  }
  return sum;
}

}  // namespace precise
}  // namespace penumbra
