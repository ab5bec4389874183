#include "bench/lib/glossy_direct.h"

#include <chrono>
#include <cmath>
#include <ctime>
#include <stdexcept>

#include "core/util/parallel.h"

namespace penumbra {

namespace {

// A point of a convex polygon from (u1, u2) in [0, 1)², uniform in area. A parallelogram maps
// the unit square bilinearly (strata stay rectangles); others go through the triangle fan.
Vec3 sampleLight(const Polygon3& poly, double u1, double u2) {
  const Vec3 e1 = poly[1] - poly[0], e3 = poly[poly.size() - 1] - poly[0];
  if (poly.size() == 4 &&
      glm::length(poly[2] - (poly[0] + e1 + e3)) <= 1e-12 * glm::length(e1 + e3))
    return poly[0] + u1 * e1 + u2 * e3;
  std::vector<double> cumulative;
  double total = 0;
  for (size_t k = 1; k + 1 < poly.size(); ++k) {
    total += glm::length(glm::cross(poly[k] - poly[0], poly[k + 1] - poly[0]));
    cumulative.push_back(total);
  }
  size_t k = 0;
  while (k + 1 < cumulative.size() && u1 * total >= cumulative[k]) ++k;
  const double lo = k ? cumulative[k - 1] : 0.0, width = cumulative[k] - lo;
  const double v1 = width > 0 ? std::clamp((u1 * total - lo) / width, 0.0, 1.0) : 0.5;
  const double s = std::sqrt(v1);
  return (1 - s) * poly[0] + s * (1 - u2) * poly[k + 1] + s * u2 * poly[k + 2];
}

// Back faces are passed through by re-tracing just past them (as render() does).
constexpr int kMaxBackFaceSkips = 64;
constexpr double kSkipRelative = 1e-5;

double processCpuSeconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

}  // namespace

ShadowRayDirect::ShadowRayDirect(const Scene& scene, const RayScene& rays)
    : scene_(scene), rays_(rays) {
  std::vector<int> ofMaterial(scene.materials().size(), -1);
  for (size_t i = 0; i < scene.materials().size(); ++i) {
    if (scene.materials()[i].type == MaterialType::Diffuse) continue;
    ofMaterial[i] = int(bsdfs_.size());
    bsdfs_.emplace_back(walkParamsOf(scene.materials()[i]));
  }
  for (const Face& face : scene.faces()) {
    const auto m = scene.findMaterial(scene.object(face.id.object).material);
    bsdfOfFace_.push_back(m ? ofMaterial[*m] : -1);
  }
}

Vec3 ShadowRayDirect::operator()(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer,
                                 int samples, bsdf::Rng& rng) const {
  const bsdf::MicrofacetBsdf& bsdf = bsdfs_[size_t(bsdfOfFace_[faceIndex])];
  // The shading frame of MicrofacetShading: tangent along the face's first edge.
  const Face& face = scene_.faces()[faceIndex];
  const Vec3 n = face.plane.normal;
  Vec3 t = face.polygon[1] - face.polygon[0];
  t = glm::normalize(t - glm::dot(t, n) * n);
  const Vec3 b = glm::cross(n, t);
  auto local = [&](const Vec3& w) { return Vec3(glm::dot(w, t), glm::dot(w, b), glm::dot(w, n)); };
  const Vec3 wo = local(toViewer);
  // The DM side's stratification (MicrofacetShading::direct on one piece): rows × columns >=
  // samples.
  const int rows = std::max(1, int(std::floor(std::sqrt(double(std::max(1, samples))))));
  const int columns = std::max(1, (samples + rows - 1) / rows);
  Vec3 sum(0.0);
  for (const Light& light : scene_.lights()) {
    const Vec3 lightNormal = light.plane().normal;
    Vec3 lightSum(0.0);
    for (int i = 0; i < rows; ++i)
      for (int j = 0; j < columns; ++j) {
        const Vec3 q =
            sampleLight(light.polygon, (i + rng.uniform()) / rows, (j + rng.uniform()) / columns);
        const Vec3 d = q - p;
        const double r2 = glm::dot(d, d);
        if (!(r2 > 0)) continue;
        const Vec3 wi = d / std::sqrt(r2);
        const double cosLight = -glm::dot(lightNormal, wi);
        const Vec3 wiLocal = local(wi);
        // Cheap rejections first, as any path tracer does: no ray where the BSDF or the light is 0.
        if (cosLight <= 0 || wiLocal.z <= 0 || rays_.occluded(p, q)) continue;
        lightSum += bsdf.eval(wo, wiLocal, rng) * (wiLocal.z * cosLight / r2);
      }
    sum += light.radiance * lightSum * (light.area() / (rows * columns));
  }
  return sum;
}

GlossyView::GlossyView(const Scene& scene, const RayScene& rays, const Camera& camera, int width,
                       int height, std::function<bool(uint32_t)> isMicrofacet)
    : scene_(scene),
      rays_(rays),
      camera_(camera, width, height),
      isMicrofacet_(std::move(isMicrofacet)) {
  mask_.assign(size_t(width) * size_t(height), 0);
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < width; ++i) {
      const auto hit = primaryHit(i, j);
      if (hit && isMicrofacet_(hit->faceIndex)) {
        mask_[size_t(j) * size_t(width) + size_t(i)] = 1;
        ++glossyPixels_;
      }
    }
}

std::optional<RayScene::Hit> GlossyView::primaryHit(int i, int j) const {
  const CameraProjection::Ray ray = camera_.rayThrough(Vec2(i + 0.5, j + 0.5));
  double tNear = 0;
  for (int pass = 0; pass < kMaxBackFaceSkips; ++pass) {
    auto hit = rays_.intersect(ray.origin, ray.dir, tNear, 1.0);
    if (!hit || hit->frontFacing) return hit;
    tNear = hit->t + kSkipRelative * std::max(hit->t, 1e-3);
  }
  return std::nullopt;
}

GlossyView::Run GlossyView::render(const DirectFn& estimate, int samples, uint64_t seed,
                                   int threads) const {
  Run run;
  run.linear.assign(3 * mask_.size(), 0.0f);
  const auto start = std::chrono::steady_clock::now();
  const double cpuStart = processCpuSeconds();
  Parallel(threads).forEach(size_t(height()), [&](size_t row) {
    const int j = int(row);
    // One generator per row: seeding a Mersenne twister costs about a microsecond, as much as a
    // few samples, and both estimators would pay it per pixel.
    bsdf::Rng rng(seed * 0x9E3779B97F4A7C15ull + row);
    for (int i = 0; i < width(); ++i) {
      const auto hit = primaryHit(i, j);
      if (!hit || !isMicrofacet_(hit->faceIndex)) continue;
      const size_t p = size_t(j) * size_t(width()) + size_t(i);
      const Vec3 toViewer = -glm::normalize(camera_.rayThrough(Vec2(i + 0.5, j + 0.5)).dir);
      const Vec3 value = estimate(hit->faceIndex, hit->position, toViewer, samples, rng);
      for (int c = 0; c < 3; ++c) run.linear[3 * p + size_t(c)] = float(value[c]);
    }
  });
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  run.cpuSeconds = processCpuSeconds() - cpuStart;
  return run;
}

}  // namespace penumbra
