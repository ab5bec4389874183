// Rays and hits in voxel space (voxel i sits at integer coordinate i; the cell of voxel i
// spans [i, i + 1]) and the clip to the traced box. Plain values; thread-safe.
#pragma once

#include <optional>

#include "core/geom/vec.h"

namespace penumbra::volume {

struct VolumeRay {
  Vec3 origin{0.0};
  Vec3 dir{0.0, 0.0, 1.0};  // need not be unit length; t is in units of |dir|
  double tMin = 0.0;
  double tMax = 1e300;
};

struct VolumeHit {
  double t = 0.0;
  Vec3 normal{0.0};  // unit gradient of the trilinear field (points towards larger values)
};

// The traced box is [0, size − 1] per axis: the trilinear interpolant of the data only, the
// same on every side (see DESIGN.md "Volumes" on where this departs from the paper).
struct TSpan {
  double t0, t1;
};
inline std::optional<TSpan> clipToBox(const VolumeRay& ray, const Vec3& lo, const Vec3& hi) {
  double t0 = ray.tMin, t1 = ray.tMax;
  for (int a = 0; a < 3; ++a) {
    if (ray.dir[a] == 0.0) {
      if (ray.origin[a] < lo[a] || ray.origin[a] > hi[a]) return std::nullopt;
      continue;
    }
    const double inv = 1.0 / ray.dir[a];
    double ta = (lo[a] - ray.origin[a]) * inv, tb = (hi[a] - ray.origin[a]) * inv;
    if (ta > tb) std::swap(ta, tb);
    t0 = ta > t0 ? ta : t0;
    t1 = tb < t1 ? tb : t1;
  }
  if (!(t0 <= t1)) return std::nullopt;
  return TSpan{t0, t1};
}

}  // namespace penumbra::volume
