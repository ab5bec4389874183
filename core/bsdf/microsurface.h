// A Smith microsurface: GGX or Beckmann normals, isotropic or anisotropic alpha, over the
// full sphere of directions (seed 004 eq. 3). Local frame: +z is the macro normal. Plain value; thread-safe.
#pragma once

#include <glm/glm.hpp>
#include <numbers>

namespace penumbra::bsdf {

using Vec3 = glm::dvec3;

inline constexpr double kPi = std::numbers::pi;

enum class Ndf { GGX, Beckmann };

struct Microsurface {
  Ndf ndf = Ndf::GGX;
  double alphaX = 0.5;
  double alphaY = 0.5;

  // Normal distribution D(m) per unit solid angle of unit m; zero below the macrosurface.
  double D(const Vec3& m) const;
  // Smith Λ over the full sphere: Λ(-ω) = -1 - Λ(ω), so Λ < -1 below the macrosurface.
  double lambda(const Vec3& w) const;
  // Λ of the upward one of ±w (>= 0): the form the full-sphere terms are written in.
  double lambdaUp(const Vec3& w) const;
  // Distant shadowing-masking |1 / (1 + Λ(ω))| (eq. 3): > 1 possible for ω below.
  double g1Dist(const Vec3& w) const;
  // ∫ <ω, m> D(m) dm: area of the microfacets facing ω, projected along ω, per unit macro area.
  double projectedArea(const Vec3& w) const;
  // Visible normals D_ω(m) = <ω, m> D(m) / projectedArea(ω), for ω on the whole sphere.
  double visibleNormalPdf(const Vec3& w, const Vec3& m) const;
  // Samples D_ω from two uniforms in [0, 1); ω may point below the macrosurface.
  Vec3 sampleVisibleNormal(const Vec3& w, double u1, double u2) const;
};

// The inverse error function (Beckmann slope sampling).
double erfInv(double y);

}  // namespace penumbra::bsdf
