// Test-side truth for core/illum: which faces block part of a light from a point
// (an exact superset, computed here without core/illum), generated scenes, cells.
// Header-only helpers for the test_illum binary; no shared state.
#pragma once

#include <algorithm>
#include <random>
#include <vector>

#include "core/dmtree/occluder_list.h"
#include "core/geom/clip.h"
#include "core/reference/exact_irradiance.h"
#include "scenegen/cubes_scene.h"

namespace penumbra::illum_test {

inline std::vector<size_t> indicesOfIds(const Scene& scene, const std::vector<FaceId>& ids) {
  std::vector<size_t> out;
  for (size_t i = 0; i < scene.faces().size(); ++i)
    if (std::find(ids.begin(), ids.end(), scene.faces()[i].id) != ids.end()) out.push_back(i);
  return out;
}

// Every face that may block part of `light` from p: p more than onPlane() behind its
// plane and some of the face inside the cone from p over the light's front part,
// between p and the light. The cone is widened by a small margin, so the set is a
// superset of the true blockers (faces that merely touch the cone's boundary are in).
inline std::vector<FaceId> blockersOf(const Scene& scene, size_t light, const Vec3& p,
                                      const Vec3& n) {
  const Tolerance tol = scene.tolerance();
  const double margin = 1e3 * tol.length();
  const Light& source = scene.lights()[light];
  const Plane lightPlane = source.plane();
  const double height = lightPlane.signedDistance(p);
  if (height <= tol.length()) return {};
  const Polygon3 front = clipFront(source.polygon, Plane::throughPoint(n, p), tol.length());
  if (front.size() < 3) return {};
  std::vector<Plane> bounds;
  const Vec3 mid = centroid(front);
  for (size_t i = 0; i < front.size(); ++i) {
    Vec3 normal = glm::cross(front[i] - p, front[(i + 1) % front.size()] - p);
    if (glm::length(normal) == 0) continue;
    normal = glm::normalize(normal);
    if (glm::dot(normal, mid - p) < 0) normal = -normal;
    bounds.push_back(Plane{normal, -glm::dot(normal, p) + margin});
  }
  bounds.push_back(Plane{lightPlane.normal, lightPlane.offset + margin});
  std::vector<FaceId> out;
  for (const Face& face : scene.faces()) {
    if (!(face.plane.signedDistance(p) < -tol.onPlane())) continue;
    Polygon3 part = face.polygon;
    for (const Plane& b : bounds) {
      part = clipFront(part, b, 0.0);
      if (part.size() < 3) break;
    }
    if (part.size() >= 3) out.push_back(face.id);
  }
  return out;
}

// Whether `face` alone hides the whole of `light` from p (a legitimate umbra flag),
// decided by the reference on a scene holding only that face.
inline bool hidesAlone(const Scene& scene, size_t light, const Face& face, const Vec3& p,
                       const Vec3& n) {
  Object object;
  object.id = "alone";
  object.vertices = face.polygon;
  std::vector<int> indices;
  for (size_t i = 0; i < face.polygon.size(); ++i) indices.push_back(int(i));
  object.faces = {indices};
  const Scene alone({scene.lights()[light]}, {}, {object});
  const LightVisibility v = ExactReference(alone).visibility(p, n, 0);
  return v.unoccludedFactor > 0 && v.lightClass == LightClass::Umbra;
}

// A cell's list for one light: `faces`, those in `umbra` flagged and first.
inline void appendEntries(OccluderList& list, uint32_t light, const std::vector<FaceId>& faces,
                          const std::vector<FaceId>& umbra = {}) {
  std::vector<OccluderEntry> flagged, partial;
  for (const FaceId& f : faces) {
    const bool isUmbra = std::find(umbra.begin(), umbra.end(), f) != umbra.end();
    (isUmbra ? flagged : partial).push_back(OccluderEntry{light, f, isUmbra});
  }
  // Umbra entries of all lights stay ahead of every partial one of the same light.
  list.insert(list.begin(), flagged.begin(), flagged.end());
  list.insert(list.end(), partial.begin(), partial.end());
}

inline std::vector<FaceId> unite(std::vector<FaceId> a, const std::vector<FaceId>& b) {
  for (const FaceId& f : b)
    if (std::find(a.begin(), a.end(), f) == a.end()) a.push_back(f);
  return a;
}

// The scene options for generated scene number k: small N, all the variants.
inline CubesSceneOptions sceneOptions(int k, int maxCubes = 8) {
  CubesSceneOptions o;
  o.seed = 1000 + uint64_t(k);
  o.cubes = 2 + k % (maxCubes - 1);
  o.lightScale = (k / 2) % 2 ? 0.2 : 1.0;
  o.tiltedLight = (k / 4) % 2 == 1;
  o.twoLights = (k / 8) % 2 == 1;
  o.stackedFraction = (k / 3) % 2 ? 0.5 : 0.2;
  o.thinTables = (k / 5) % 3 == 0 ? 0.0 : 0.3;
  return o;
}

// A uniformly random point of a convex face.
inline Vec3 randomPointOn(const Face& face, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0, 1);
  const Polygon3& poly = face.polygon;
  std::vector<double> areas;
  double total = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    areas.push_back(0.5 * glm::length(glm::cross(poly[i] - poly[0], poly[i + 1] - poly[0])));
    total += areas.back();
  }
  double pick = u(rng) * total;
  size_t t = 0;
  while (t + 1 < areas.size() && pick > areas[t]) pick -= areas[t++];
  double a = u(rng), b = u(rng);
  if (a + b > 1) a = 1 - a, b = 1 - b;
  return poly[0] + a * (poly[t + 1] - poly[0]) + b * (poly[t + 2] - poly[0]);
}

// Peak irradiance of the scene (per channel max): the floor below each light.
inline double peakIrradiance(const Scene& scene) {
  const ExactReference reference(scene);
  double peak = 0;
  for (const Light& light : scene.lights()) {
    const Vec3 c = centroid(light.polygon);
    const PointIrradiance e = reference.evaluate(Vec3(c.x, 0, c.z), Vec3(0, 1, 0));
    peak = std::max({peak, e.irradiance.x, e.irradiance.y, e.irradiance.z});
  }
  return peak;
}

inline double maxAbs(const Vec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

}  // namespace penumbra::illum_test
