#include "core/render/microfacet_shading.h"

#include <algorithm>
#include <cmath>

namespace penumbra {
namespace {

// One convex piece as a sampling domain: its fan triangles with cumulative areas.
struct PieceSampler {
  const Polygon3* piece = nullptr;
  // Area up to and including fan triangle k: (poly[0], poly[k + 1], poly[k + 2]).
  std::vector<double> cumulative;
  bool parallelogram = false;  // sampled bilinearly: rectangular strata

  void assign(const Polygon3& poly) {
    piece = &poly;
    cumulative.clear();
    double total = 0;
    for (size_t k = 1; k + 1 < poly.size(); ++k)
      cumulative.push_back(total +=
                           0.5 * glm::length(glm::cross(poly[k] - poly[0], poly[k + 1] - poly[0])));
    parallelogram = poly.size() == 4 && glm::length(poly[2] - poly[1] - poly[3] + poly[0]) <=
                                            1e-12 * glm::length(poly[2] - poly[0]);
  }
  double area() const { return cumulative.empty() ? 0.0 : cumulative.back(); }

  // A point uniform in area from (u1, u2) in [0, 1)²: u1 picks a fan triangle by cumulative area
  // and is rescaled inside it, so strata of (u1, u2) stay strata.
  Vec3 sample(double u1, double u2) const {
    const Polygon3& poly = *piece;
    if (parallelogram) return poly[0] + u1 * (poly[1] - poly[0]) + u2 * (poly[3] - poly[0]);
    const double total = cumulative.back();
    const size_t k = size_t(std::upper_bound(cumulative.begin(), cumulative.end() - 1, u1 * total) -
                            cumulative.begin());
    const double lo = k ? cumulative[k - 1] : 0.0, width = cumulative[k] - lo;
    const double v1 = width > 0 ? std::clamp((u1 * total - lo) / width, 0.0, 1.0) : 0.5;
    const double s = std::sqrt(v1);
    return (1 - s) * poly[0] + s * (1 - u2) * poly[k + 1] + s * u2 * poly[k + 2];
  }
};

// A rows × columns stratification of at least n points, as square as n allows.
std::pair<int, int> strataOf(int n) {
  const int rows = std::max(1, int(std::floor(std::sqrt(double(n)))));
  return {rows, std::max(1, (n + rows - 1) / rows)};
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
  const int budget = std::max(1, samples);
  Vec3 sum(0.0);
  std::vector<Polygon3> pieces;
  std::vector<PieceSampler> samplers;
  for (size_t l = 0; l < scene_.lights().size(); ++l) {
    const Light& light = scene_.lights()[l];
    const Vec3 lightNormal = light.plane().normal;
    pieces.clear();
    visible_(faceIndex, p, l, pieces);
    samplers.resize(pieces.size());
    double visibleArea = 0;
    for (size_t k = 0; k < pieces.size(); ++k) {
      samplers[k].assign(pieces[k]);
      visibleArea += samplers[k].area();
    }
    for (const PieceSampler& piece : samplers) {
      if (!(piece.area() > 0)) continue;
      // The light's budget split by area, each piece stratified on its own (compact strata).
      const auto [rows, columns] = strataOf(int(std::lround(budget * piece.area() / visibleArea)));
      Vec3 pieceSum(0.0);
      for (int i = 0; i < rows; ++i)
        for (int j = 0; j < columns; ++j) {
          const Vec3 q = piece.sample((i + rng.uniform()) / rows, (j + rng.uniform()) / columns);
          const Vec3 d = q - p;
          const double r2 = glm::dot(d, d);
          if (!(r2 > 0)) continue;
          const Vec3 wi = d / std::sqrt(r2);
          const double cosLight = -glm::dot(lightNormal, wi);
          if (cosLight <= 0) continue;
          const Vec3 wiLocal = frame.toLocal(wi);
          pieceSum += bsdf.eval(wo, wiLocal, rng) * (std::abs(wiLocal.z) * cosLight / r2);
        }
      sum += light.radiance * pieceSum * (piece.area() / (rows * columns));
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
