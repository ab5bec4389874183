#include "core/gi/view_gbuffer.h"

namespace penumbra::gi {

GBuffer viewGBuffer(const RayScene& rays, const Camera& camera, int width, int height, const Parallel& parallel) {
  const CameraProjection projection(camera, width, height);
  const size_t pixels = size_t(width) * size_t(height);
  GBuffer g{width, height, std::vector<int32_t>(pixels, -1), std::vector<Vec3>(pixels, Vec3(0.0))};
  parallel.forEach(size_t(height), [&](size_t row) {
    for (int i = 0; i < width; ++i) {
      const auto ray = projection.rayThrough(Vec2(i + 0.5, double(row) + 0.5));
      if (const auto hit = rays.intersectFront(ray.origin, ray.dir, 0, 1.0)) {
        const size_t p = row * size_t(width) + size_t(i);
        g.face[p] = int32_t(hit->faceIndex);
        g.position[p] = hit->position;
      }
    }
  });
  return g;
}

}  // namespace penumbra::gi
