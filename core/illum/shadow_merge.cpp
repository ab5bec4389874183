#include "core/illum/shadow_merge.h"

#include <algorithm>
#include <cmath>

#include "core/scene/convex_solid.h"

namespace penumbra {

bool mergeableShadows(const Scene& scene, uint32_t handle, const Plane& lightPlane, const Vec3& p) {
  const ConvexSolid* solid = scene.convexSolid(handle);
  if (!solid) return false;
  // The solid's corners are its faces' corners, each once.
  for (const Vec3& v : solid->vertices)
    if (!mergeableCorner(lightPlane.signedDistance(v), scene.tolerance())) return false;
  for (const Face& face : scene.facesOfObject(handle))
    if (!mergeableFaceSide(face.plane.signedDistance(p), scene.tolerance())) return false;
  return true;
}

void convexHullInto(std::span<const Vec2> points, double eps, std::vector<Vec2>& out) {
  thread_local std::vector<Vec2> sorted;
  sorted.assign(points.begin(), points.end());
  std::sort(sorted.begin(), sorted.end(),
            [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  out.clear();
  if (sorted.size() < 3) return;
  // Andrew's monotone chain: lower hull left to right, upper hull back, strict left turns.
  auto turn = [](const Vec2& o, const Vec2& a, const Vec2& b) { return cross2(a - o, b - o); };
  for (const Vec2& q : sorted) {
    while (out.size() >= 2 && !(turn(out[out.size() - 2], out.back(), q) > 0)) out.pop_back();
    out.push_back(q);
  }
  const size_t lower = out.size() + 1;
  for (size_t i = sorted.size() - 1; i-- > 0;) {
    while (out.size() >= lower && !(turn(out[out.size() - 2], out.back(), sorted[i]) > 0))
      out.pop_back();
    out.push_back(sorted[i]);
  }
  out.pop_back();  // the first point again
  // Corners within eps of the previous one (one corner clipped apart on two faces) are one.
  size_t kept = 0;
  for (size_t i = 0; i < out.size(); ++i)
    if (kept == 0 || glm::length(out[i] - out[kept - 1]) > eps) out[kept++] = out[i];
  while (kept > 1 && glm::length(out[0] - out[kept - 1]) <= eps) --kept;
  out.resize(kept < 3 ? 0 : kept);
}

bool mergeShadowGroups(std::span<const Vec2> points, std::span<const uint32_t> starts,
                       std::span<const uint32_t> groups, double eps, std::vector<Vec2>& outPoints,
                       std::vector<uint32_t>& outStarts) {
  thread_local std::vector<Vec2> gathered, hull;
  thread_local std::vector<uint8_t> done;
  const size_t count = groups.size();
  done.assign(count, 0);
  outPoints.clear();
  outStarts.assign(1, 0);
  bool merged = false;
  auto shadow = [&](size_t i) { return points.subspan(starts[i], starts[i + 1] - starts[i]); };
  auto append = [&](std::span<const Vec2> polygon) {
    outPoints.insert(outPoints.end(), polygon.begin(), polygon.end());
    outStarts.push_back(uint32_t(outPoints.size()));
  };
  for (size_t i = 0; i < count; ++i) {
    if (done[i]) continue;
    size_t members = 1;
    if (groups[i] != kNoGroup)
      for (size_t j = i + 1; j < count; ++j) members += groups[j] == groups[i];
    if (members == 1) {
      append(shadow(i));
      continue;
    }
    gathered.clear();
    for (size_t j = i; j < count; ++j)
      if (groups[j] == groups[i]) {
        gathered.insert(gathered.end(), shadow(j).begin(), shadow(j).end());
        done[j] = 1;
      }
    convexHullInto(gathered, eps, hull);
    if (hull.size() >= 3) append(hull);
    merged = true;
  }
  return merged;
}

}  // namespace penumbra
