// Independent reference for core/bsdf: the microsurface random walk WITH sampled heights of
// Heitz et al. 2016 (GGX or Beckmann, uniform height distribution), sharing no code with core/bsdf.
// Pure; thread-safe given one generator per thread.
#pragma once

#include <cstdint>
#include <optional>
#include <random>

#include <glm/glm.hpp>

namespace penumbra::bench {

struct HeitzSurface {
  enum class Kind { Conductor, Diffuse, Dielectric };
  enum class Ndf { GGX, Beckmann };
  Ndf ndf = Ndf::GGX;
  double alphaX = 1, alphaY = 1;
  Kind kind = Kind::Conductor;    // conductor: F = 1; diffuse: albedo 1
  double ior = 1.5;               // dielectric: below the macrosurface / above
  int maxBounces = 256;
};

struct HeitzExit {
  glm::dvec3 direction;  // +z = macro normal; below = transmitted
  int bounces = 0;
};

// Light arriving from wi (pointing away from the surface, either side for a dielectric);
// nothing when the walk reaches maxBounces.
std::optional<HeitzExit> heitzWalk(const HeitzSurface& s, const glm::dvec3& wi, std::mt19937_64& gen);

}  // namespace penumbra::bench
