#include "core/volume/cell_hit.h"

#include <algorithm>
#include <cmath>

namespace penumbra::volume {

CellCubic cellCubic(const CellCorners& corners, const Vec3& local, const Vec3& dir, double iso) {
  // Each corner weight is a product of three linear factors (1 − x or x along the ray).
  CellCubic out{0.0, 0.0, 0.0, -iso};
  for (int corner = 0; corner < 8; ++corner) {
    double p0 = 1.0, p1 = 0.0, p2 = 0.0, p3 = 0.0;  // running product, coefficients of t^k
    for (int axis = 0; axis < 3; ++axis) {
      const bool upper = (corner >> (2 - axis)) & 1;
      const double q0 = upper ? local[axis] : 1.0 - local[axis];
      const double q1 = upper ? dir[axis] : -dir[axis];
      p3 = p3 * q0 + p2 * q1;
      p2 = p2 * q0 + p1 * q1;
      p1 = p1 * q0 + p0 * q1;
      p0 = p0 * q0;
    }
    const double v = corners[corner];
    out.a += v * p3;
    out.b += v * p2;
    out.c += v * p1;
    out.d += v * p0;
  }
  return out;
}

namespace {

bool above(double g) { return g > 0.0; }

// Illinois regula falsi on [lo, hi] with a sign change; keeps the bracket.
double refine(const CellCubic& cubic, double lo, double hi, double glo, double ghi) {
  const double eps = 1e-13 * std::max(1.0, hi - lo);
  int side = 0;
  for (int i = 0; i < 200 && hi - lo > eps; ++i) {
    double t = (lo * ghi - hi * glo) / (ghi - glo);
    if (!(t > lo && t < hi)) t = 0.5 * (lo + hi);
    const double g = cubic.at(t);
    if (g == 0.0) return t;
    if (above(g) == above(glo)) {
      lo = t, glo = g;
      if (side == -1) ghi *= 0.5;
      side = -1;
    } else {
      hi = t, ghi = g;
      if (side == 1) glo *= 0.5;
      side = 1;
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

std::optional<double> firstRoot(const CellCubic& cubic, double t0, double t1) {
  // Split points: roots of the derivative 3a t² + 2b t + c inside (t0, t1), in order.
  double split[4] = {t0, t1, t1, t1};
  int count = 1;
  const double qa = 3.0 * cubic.a, qb = 2.0 * cubic.b, qc = cubic.c;
  double roots[2];
  int found = 0;
  if (qa != 0.0) {
    const double disc = qb * qb - 4.0 * qa * qc;
    if (disc >= 0.0) {
      // Numerically stable pair (no cancellation between -qb and the square root).
      const double q = -0.5 * (qb + std::copysign(std::sqrt(disc), qb));
      if (q != 0.0) roots[found++] = qc / q;
      roots[found++] = q / qa;
    }
  } else if (qb != 0.0) {
    roots[found++] = -qc / qb;
  }
  if (found == 2 && roots[0] > roots[1]) std::swap(roots[0], roots[1]);
  for (int i = 0; i < found; ++i)
    if (roots[i] > t0 && roots[i] < t1) split[count++] = roots[i];
  split[count++] = t1;
  double lo = split[0], glo = cubic.at(lo);
  for (int i = 1; i < count; ++i) {
    const double hi = split[i], ghi = cubic.at(hi);
    if (above(glo) != above(ghi)) {
      if (glo == 0.0) return lo;  // f ≤ iso at lo counts as "not above": lo is the crossing
      return refine(cubic, lo, hi, glo, ghi);
    }
    lo = hi, glo = ghi;
  }
  return std::nullopt;
}

Vec3 trilinearGradient(const CellCorners& c, const Vec3& p) {
  Vec3 g{0.0};
  for (int corner = 0; corner < 8; ++corner) {
    const int bx = (corner >> 2) & 1, by = (corner >> 1) & 1, bz = corner & 1;
    const double wx = bx ? p.x : 1.0 - p.x, wy = by ? p.y : 1.0 - p.y, wz = bz ? p.z : 1.0 - p.z;
    const double sx = bx ? 1.0 : -1.0, sy = by ? 1.0 : -1.0, sz = bz ? 1.0 : -1.0;
    g += c[corner] * Vec3{sx * wy * wz, wx * sy * wz, wx * wy * sz};
  }
  return g;
}

}  // namespace penumbra::volume
