// The height of the walk's next vertex in the height-correlated model, as a distribution: seen
// from the side the ray is on, u = C1(h) has -ln u = depth + X, X ~ Exp(rate). Plain value; the
// functions that move it are pure given an Rng (thread-safe given one Rng per thread).
#pragma once

#include <limits>

#include "core/bsdf/rng.h"

namespace penumbra::bsdf {

// Smith's model over heights (Heitz et al. 2016): a ray leaving height u away from the surface
// passes u' > u with probability (u / u')^Λ; one going into it meets the surface below u at
// rate 1 + Λ(-d) per unit of -ln u; light from outside along -w first meets it at density
// c u^(c - 1), c = 1 + Λ(w) = 1 / G1(w) (seed 004 eq. 3). These keep the family closed: an
// exponential part survives a blocked ray (memoryless), and a ray into the surface adds one.
struct VertexHeight {
  double depth = 0;                                       // the sampled part of -ln u, >= 0
  double rate = std::numeric_limits<double>::infinity();  // of the unsampled part; infinite: none
};

// The first vertex of light arriving from w: rate 1 / G1(w).
inline VertexHeight firstVertex(double invG1) { return {0.0, invG1}; }

// Probability that a ray leaving the vertex away from the surface, with Smith Λ = lambda,
// escapes: E[u^Λ] = exp(-depth Λ) rate / (rate + Λ). At the first vertex: G2(w, d) / G1(w) (eq.
// 12).
double escapeAway(const VertexHeight& h, double lambda);
// The next vertex's height when that ray is blocked: its posterior (above the sampled depth the
// exponential part is unchanged; below it, a truncated exponential is sampled).
VertexHeight blockedAway(const VertexHeight& h, double lambda, Rng& rng);
// The next vertex's height for a ray going into the surface, hit at rate hitRate = 1 + Λ(-d).
VertexHeight intoSurface(const VertexHeight& h, double hitRate, Rng& rng);
// The same height seen from the other side of the interface (u -> 1 - u), sampled.
VertexHeight crossed(const VertexHeight& h, Rng& rng);
// Probability that a ray refracted to the other side, leaving it away from the surface there,
// escapes: E[(1 - u)^Λ]; rate · B(rate, 1 + Λ) at the first vertex, else a one-sample estimate.
double escapeAcross(const VertexHeight& h, double lambda, Rng& rng);

}  // namespace penumbra::bsdf
