// The ray–isosurface hit inside one cell of 8 voxels: the first root of the cubic the
// trilinear interpolant makes along the ray (Marmitt et al.'s iterative finder), and the
// normal from the trilinear gradient. Pure functions; thread-safe.
#pragma once

#include <array>
#include <optional>

#include "core/geom/vec.h"

namespace penumbra::volume {

// Corner values, index x << 2 | y << 1 | z (the paper's child numbering).
using CellCorners = std::array<double, 8>;

// f(t) − iso = a t³ + b t² + c t + d along p(t) = local + t·dir, with local in cell units.
struct CellCubic {
  double a, b, c, d;
  double at(double t) const { return ((a * t + b) * t + c) * t + d; }
};
CellCubic cellCubic(const CellCorners& corners, const Vec3& local, const Vec3& dir, double iso);

// First t in [t0, t1] where f − iso changes sign (f > iso against f ≤ iso). The cubic's
// extrema split [t0, t1] into monotone pieces; the first piece with a sign change is refined
// to ~1e-13 of the segment by the Illinois variant of regula falsi.
std::optional<double> firstRoot(const CellCubic& cubic, double t0, double t1);

// Gradient of the trilinear interpolant at local (cell units, in [0, 1]³).
Vec3 trilinearGradient(const CellCorners& corners, const Vec3& local);

}  // namespace penumbra::volume
