#include "bench/lib/direct_light_error.h"

#include <algorithm>
#include <cmath>

#include "core/gi/view_gbuffer.h"
#include "core/raycast/mesh_lookup.h"
#include "core/raycast/ray_scene.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra {

namespace {

double largest(const Vec3& v) { return std::max({v.x, v.y, v.z}); }

// The largest channel of what every light gives at p with nothing in the way.
double unshadowedAt(const Scene& scene, const ExactReference& reference, const Vec3& p, const Vec3& n) {
  Vec3 sum{0.0};
  for (size_t l = 0; l < scene.lights().size(); ++l)
    sum += reference.visibility(p, n, l).unoccludedFactor * scene.lights()[l].radiance;
  return largest(sum);
}

}  // namespace

DirectLightError directLightError(const Scene& scene, const Mesh& mesh, const Camera& camera, int width,
                                  int height, const Parallel& parallel) {
  const RayScene rays(scene);
  const gi::GBuffer view = gi::viewGBuffer(rays, camera, width, height, parallel);
  const MeshLookup lookup(scene, mesh);
  const ExactReference reference(scene);
  const size_t pixels = view.face.size();
  std::vector<double> exact(pixels, -1), error(pixels, 0), interpolated(pixels, 0);
  parallel.forEach(size_t(height), [&](size_t row) {
    for (size_t p = row * size_t(width); p < (row + 1) * size_t(width); ++p) {
      if (view.face[p] < 0) continue;
      const uint32_t faceIndex = uint32_t(view.face[p]);
      const Face& face = scene.faces()[faceIndex];
      if (!scene.receivesLight(face)) continue;
      const Vec3 truth =
          reference.evaluate(view.position[p], face.plane.normal, shadingNormal(face, view.position[p])).irradiance;
      const Vec3 mesh = lookup.irradiance(faceIndex, view.position[p]).value_or(Vec3(0.0));
      exact[p] = largest(truth);
      interpolated[p] = largest(mesh);
      error[p] = largest(glm::abs(mesh - truth));
    }
  });
  DirectLightError out;
  std::vector<double> levels;
  for (double e : exact)
    if (e >= 0) levels.push_back(e);
  out.pixels = levels.size();
  if (levels.empty()) return out;
  const size_t at = std::min(levels.size() - 1, size_t(std::floor(0.99 * double(levels.size()))));
  std::nth_element(levels.begin(), levels.begin() + long(at), levels.end());
  out.brightLevel = levels[at];
  if (!(out.brightLevel > 0)) return out;
  for (size_t p = 0; p < pixels; ++p) {
    if (exact[p] < 0) continue;
    const double relative = error[p] / out.brightLevel;
    out.overOnePercent += relative > 0.01 ? 1 : 0;
    out.overOnePercentAboveBright += relative > 0.01 && exact[p] > out.brightLevel ? 1 : 0;
    out.overTwoPercent += relative > 0.02 ? 1 : 0;
    if (relative > 0.01) {
      const uint32_t face = uint32_t(view.face[p]);
      const Vec3 normal = scene.faces()[face].plane.normal;
      out.misses.push_back({int(p % size_t(width)), int(p / size_t(width)), face, view.position[p], exact[p],
                            interpolated[p], unshadowedAt(scene, reference, view.position[p], normal)});
    }
    if (relative > out.worstRelative) {
      out.worstRelative = relative;
      out.worstX = int(p % size_t(width));
      out.worstY = int(p / size_t(width));
      out.worstMesh = interpolated[p];
      out.worstExact = exact[p];
    }
  }
  return out;
}

}  // namespace penumbra
