#include "core/render/microfacet_shading.h"

#include <cmath>

namespace penumbra {
namespace {

// A point of a convex polygon from (u1, u2) in [0, 1)², uniform in area: u1 picks a triangle of
// the fan by cumulative area and is rescaled inside it, so strata of (u1, u2) stay strata.
Vec3 samplePolygon(const Polygon3& poly, const std::vector<double>& cumulative, double u1, double u2) {
  const double total = cumulative.back();
  size_t k = 0;
  while (k + 1 < cumulative.size() && u1 * total >= cumulative[k]) ++k;
  const double lo = k ? cumulative[k - 1] : 0.0, width = cumulative[k] - lo;
  const double v1 = width > 0 ? std::clamp((u1 * total - lo) / width, 0.0, 1.0) : 0.5;
  const double s = std::sqrt(v1);  // uniform in the triangle (poly[0], poly[k+1], poly[k+2])
  return (1 - s) * poly[0] + s * (1 - u2) * poly[k + 1] + s * u2 * poly[k + 2];
}

}  // namespace

bsdf::WalkParams walkParamsOf(const Material& m) {
  bsdf::WalkParams p;
  p.surface = bsdf::Microsurface{m.ndf, m.roughness.x, m.roughness.y};
  p.facets = m.type == MaterialType::Conductor    ? bsdf::Facets::Conductor
             : m.type == MaterialType::Dielectric ? bsdf::Facets::Dielectric
                                                  : bsdf::Facets::RoughDiffuse;
  p.singleScattering = m.singleScattering;
  p.albedo = m.albedo;
  p.eta = m.eta;
  p.k = m.k;
  p.ior = m.ior;
  p.maxBounces = 64;
  return p;
}

MicrofacetShading::MicrofacetShading(const Scene& scene, const RayScene& rays, VisiblePiecesFn visible,
                                     DiffuseRadianceFn diffuse, MicrofacetSettings settings)
    : scene_(scene), rays_(rays), visible_(std::move(visible)), diffuse_(std::move(diffuse)), settings_(settings) {
  std::vector<int> ofMaterial(scene.materials().size(), -1);
  for (size_t i = 0; i < scene.materials().size(); ++i) {
    if (scene.materials()[i].type == MaterialType::Diffuse) continue;
    ofMaterial[i] = int(bsdfs_.size());
    bsdfs_.emplace_back(walkParamsOf(scene.materials()[i]));
  }
  for (const Face& face : scene.faces()) {
    const auto m = scene.findMaterial(scene.object(face.id.object).material);
    bsdfIndex_.push_back(m ? ofMaterial[*m] : -1);
  }
}

MicrofacetShading::Frame MicrofacetShading::frameOf(uint32_t faceIndex) const {
  // Tangent along the face's first edge: anisotropic roughness follows the polygon.
  const Face& face = scene_.faces()[faceIndex];
  const Vec3 n = face.plane.normal;
  Vec3 t = face.polygon[1] - face.polygon[0];
  t = glm::normalize(t - glm::dot(t, n) * n);
  return {t, glm::cross(n, t), n};
}

Vec3 MicrofacetShading::direct(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer, int samples,
                               bsdf::Rng& rng) const {
  const bsdf::MicrofacetBsdf& bsdf = bsdfs_[size_t(bsdfIndex_[faceIndex])];
  const Frame frame = frameOf(faceIndex);
  const Vec3 wo = frame.toLocal(toViewer);
  const int side = std::max(1, int(std::ceil(std::sqrt(double(samples)))));
  Vec3 sum(0.0);
  std::vector<Polygon3> pieces;
  std::vector<double> cumulative;
  for (size_t l = 0; l < scene_.lights().size(); ++l) {
    const Light& light = scene_.lights()[l];
    const Vec3 lightNormal = light.plane().normal;
    pieces.clear();
    visible_(faceIndex, p, l, pieces);
    for (const Polygon3& piece : pieces) {
      cumulative.clear();
      double area = 0;
      for (size_t k = 1; k + 1 < piece.size(); ++k) {
        area += 0.5 * glm::length(glm::cross(piece[k] - piece[0], piece[k + 1] - piece[0]));
        cumulative.push_back(area);
      }
      if (!(area > 0)) continue;
      Vec3 pieceSum(0.0);
      for (int i = 0; i < side; ++i)
        for (int j = 0; j < side; ++j) {
          const Vec3 q = samplePolygon(piece, cumulative, (i + rng.uniform()) / side, (j + rng.uniform()) / side);
          const Vec3 d = q - p;
          const double r2 = glm::dot(d, d);
          if (!(r2 > 0)) continue;
          const Vec3 wi = d / std::sqrt(r2);
          const double cosLight = -glm::dot(lightNormal, wi);
          if (cosLight <= 0) continue;
          const Vec3 wiLocal = frame.toLocal(wi);
          pieceSum += bsdf.eval(wo, wiLocal, rng) * (std::abs(wiLocal.z) * cosLight / r2);
        }
      sum += light.radiance * pieceSum * (area / (side * side));
    }
  }
  return sum;
}

Vec3 MicrofacetShading::radiance(uint32_t faceIndex, const Vec3& p, const Vec3& toViewer, bsdf::Rng& rng) const {
  Vec3 sum(0.0);
  const int paths = std::max(1, settings_.pathsPerPixel);
  for (int k = 0; k < paths; ++k) sum += indirect(faceIndex, p, toViewer, rng);
  return direct(faceIndex, p, toViewer, settings_.lightSamples, rng) + sum / double(paths);
}

Vec3 MicrofacetShading::indirect(uint32_t faceIndex, const Vec3& p0, const Vec3& toViewer0, bsdf::Rng& rng) const {
  Vec3 result(0.0), throughput(1.0);
  uint32_t face = faceIndex;
  Vec3 p = p0, toViewer = toViewer0;
  const double far = 4 * scene_.bounds().diagonal() + 1;
  const double offset = 1e-7 * (scene_.bounds().diagonal() + 1);
  for (int depth = 0; depth < settings_.maxDepth; ++depth) {
    if (depth > 0) result += throughput * direct(face, p, toViewer, std::max(1, settings_.lightSamples / 4), rng);
    if (depth + 1 == settings_.maxDepth) break;
    const Frame frame = frameOf(face);
    const bsdf::MicrofacetBsdf& bsdf = bsdfs_[size_t(bsdfIndex_[face])];
    const std::optional<bsdf::BsdfSample> s = bsdf.sample(frame.toLocal(toViewer), rng);
    if (!s) break;
    throughput *= s->weight;
    const Vec3 dir = frame.toWorld(s->wi);
    // Lights are left out: the light-piece integral at each vertex already counts them.
    const auto hit = rays_.intersect(p + offset * dir, dir, 0.0, far);
    if (!hit) break;
    if (!isMicrofacet(hit->faceIndex)) {
      result += throughput * diffuse_(hit->faceIndex, hit->position, hit->frontFacing);
      break;
    }
    // Faces are single-sided: only a dielectric is seen from behind (from inside it).
    if (!hit->frontFacing && bsdfs_[size_t(bsdfIndex_[hit->faceIndex])].params().facets != bsdf::Facets::Dielectric)
      break;
    face = hit->faceIndex;
    p = hit->position;
    toViewer = -dir;
  }
  return result;
}

}  // namespace penumbra
