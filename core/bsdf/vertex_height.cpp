#include "core/bsdf/vertex_height.h"

#include <cmath>

namespace penumbra::bsdf {
namespace {

// exp(-depth Λ) with the limits 1 for depth or Λ zero.
double decay(double depth, double lambda) {
  return depth == 0 || lambda == 0 ? 1.0 : std::exp(-depth * lambda);
}

// A sample of the exponential part (0 when there is none).
double exponentialPart(const VertexHeight& h, Rng& rng) {
  return std::isinf(h.rate) ? 0.0 : -std::log1p(-rng.uniform()) / h.rate;
}

}  // namespace

double escapeAway(const VertexHeight& h, double lambda) {
  if (std::isinf(lambda)) return 0;
  const double unsampled = std::isinf(h.rate) ? 1.0 : h.rate / (h.rate + lambda);
  return decay(h.depth, lambda) * unsampled;
}

VertexHeight blockedAway(const VertexHeight& h, double lambda, Rng& rng) {
  if (h.depth == 0 || lambda == 0 || std::isinf(lambda)) return h;
  // Blocked above the sampled depth (mass Λ / (rate + Λ)): the exponential part again.
  const double above = std::isinf(h.rate) ? 0.0 : lambda / (h.rate + lambda);
  if (rng.uniform() * (1.0 - escapeAway(h, lambda)) < above) return h;
  // Below it: -ln u' = depth - t, t ~ Exp(Λ) truncated to (0, depth).
  const double t = -std::log1p(rng.uniform() * std::expm1(-lambda * h.depth)) / lambda;
  return {std::max(0.0, h.depth - t), std::numeric_limits<double>::infinity()};
}

VertexHeight intoSurface(const VertexHeight& h, double hitRate, Rng& rng) {
  return {h.depth + exponentialPart(h, rng), hitRate};
}

VertexHeight crossed(const VertexHeight& h, Rng& rng) {
  const double e = h.depth + exponentialPart(h, rng);                            // -ln u
  return {-std::log(-std::expm1(-e)), std::numeric_limits<double>::infinity()};  // -ln(1 - u)
}

double escapeAcross(const VertexHeight& h, double lambda, Rng& rng) {
  if (std::isinf(lambda)) return 0;
  if (h.depth == 0) {
    if (std::isinf(h.rate))
      return lambda == 0 ? 1.0 : 0.0;  // at the very top: the bottom is out of reach
    // rate B(rate, 1 + Λ) = Γ(rate + 1) Γ(1 + Λ) / Γ(rate + 1 + Λ), in logs for a large rate.
    return std::exp(std::lgamma(h.rate + 1.0) + std::lgamma(1.0 + lambda) -
                    std::lgamma(h.rate + 1.0 + lambda));
  }
  return decay(crossed(h, rng).depth, lambda);
}

}  // namespace penumbra::bsdf
