#include "core/volume/octree_trace.h"

#include <algorithm>

#include "core/volume/cell_hit.h"
#include "core/volume/octant_order.h"

namespace penumbra::volume {

namespace {

template <class T>
class Tracer {
 public:
  Tracer(const OctreeVolume<T>& volume, const VolumeRay& ray, double iso, TraceCounters* counters)
      : v_(volume), o_(ray.origin), d_(ray.dir), iso_(iso), counters_(counters) {
    for (int a = 0; a < 3; ++a) inv_[a] = d_[a] != 0.0 ? 1.0 / d_[a] : 0.0;
  }

  std::optional<VolumeHit> run(double t0, double t1) {
    if (node(0, 0, glm::ivec3(0), t0, t1)) return hit_;
    return std::nullopt;
  }

 private:
  const OctreeVolume<T>& v_;
  Vec3 o_, d_, inv_;
  double iso_;
  TraceCounters* counters_;
  VolumeHit hit_;
  // The path from the root (the paper's parent_trace): where neighbour finding starts.
  uint32_t traceIndex_[32];
  glm::ivec3 traceOrigin_[32];

  int half(int depth) const { return 1 << (v_.maxDepth() - depth - 1); }
  bool holds(double lo, double hi) const { return lo <= iso_ && iso_ < hi; }

  bool node(int depth, uint32_t index, glm::ivec3 origin, double t0, double t1) {
    if (counters_) ++counters_->nodes;
    const OctNode<T>& n = v_.nodes(depth)[index];
    traceIndex_[depth] = index;
    traceOrigin_[depth] = origin;
    const int h = half(depth);
    return walkOctants(o_, d_, inv_, Vec3(origin + h), t0, t1, [&](int c, double ta, double tb) {
      if (!holds(double(n.childMins[c]), double(n.childMaxs[c]))) return false;
      const glm::ivec3 co = origin + octant(c) * h;
      if (n.childOffset[c] < 0)
        return uniform(depth, co, h, double(n.childScalars[c]), co, h, ta, tb);
      const uint32_t child = n.childStart + uint32_t(n.childOffset[c]);
      if (depth == v_.maxDepth() - 2) return cap(depth, child, co, ta, tb);
      return node(depth + 1, child, co, ta, tb);
    });
  }

  // A cap: its 8 voxels are the cells' lower corners; forward corners outside the cap come
  // from neighbour finding.
  bool cap(int parentDepth, uint32_t index, glm::ivec3 origin, double t0, double t1) {
    const OctCap<T>& cap = v_.caps()[index];
    return walkOctants(o_, d_, inv_, Vec3(origin + 1), t0, t1, [&](int c, double ta, double tb) {
      CellCorners corners;
      for (int dir = 0; dir < 8; ++dir)
        corners[dir] = (c & dir) == 0 ? double(cap.scalars[c | dir])
                                      : neighbour(parentDepth, origin + octant(c) + octant(dir));
      return cell(corners, origin + octant(c), ta, tb);
    });
  }

  // A scalar leaf of value `value` over [block, block + size): only cells touching its
  // forward faces can differ from `value`; the rest are skipped octant by octant.
  bool uniform(int parentDepth, glm::ivec3 block, int size, double value, glm::ivec3 sub,
               int subSize, double t0, double t1) {
    const glm::ivec3 end = block + size;
    if (sub.x + subSize < end.x && sub.y + subSize < end.y && sub.z + subSize < end.z) return false;
    if (subSize == 1) {
      CellCorners corners;
      for (int dir = 0; dir < 8; ++dir) {
        const glm::ivec3 p = sub + octant(dir);
        corners[dir] =
            p.x < end.x && p.y < end.y && p.z < end.z ? value : neighbour(parentDepth, p);
      }
      return cell(corners, sub, t0, t1);
    }
    const int h = subSize / 2;
    return walkOctants(o_, d_, inv_, Vec3(sub + h), t0, t1, [&](int c, double ta, double tb) {
      return uniform(parentDepth, block, size, value, sub + octant(c) * h, h, ta, tb);
    });
  }

  // Neighbour finding: up the traced path to the first node holding p, then down.
  double neighbour(int deepest, glm::ivec3 p) {
    if (counters_) ++counters_->neighbours;
    int depth = deepest;
    for (; depth > 0; --depth) {
      const glm::ivec3 q = p - traceOrigin_[depth];
      const int side = 2 * half(depth);
      if (q.x >= 0 && q.y >= 0 && q.z >= 0 && q.x < side && q.y < side && q.z < side) break;
    }
    return double(v_.locateFrom(depth, traceIndex_[depth], p));
  }

  bool cell(const CellCorners& corners, glm::ivec3 voxel, double t0, double t1) {
    if (counters_) ++counters_->cells;
    const auto [lo, hi] = std::minmax_element(corners.begin(), corners.end());
    if (!holds(*lo, *hi) || !(t0 <= t1)) return false;
    if (counters_) ++counters_->cubics;
    // The cubic in s = t − t0 from the segment's entry point: coefficients stay O(1).
    const Vec3 entry = o_ + d_ * t0 - Vec3(voxel);
    const std::optional<double> s = firstRoot(cellCubic(corners, entry, d_, iso_), 0.0, t1 - t0);
    if (!s) return false;
    hit_.t = t0 + *s;
    const Vec3 g = trilinearGradient(corners, entry + d_ * *s);
    const double length = glm::length(g);
    hit_.normal = length > 0.0 ? g / length : -glm::normalize(d_);
    return true;
  }
};

}  // namespace

template <class T>
std::optional<VolumeHit> traceOctree(const OctreeVolume<T>& volume, const VolumeRay& ray,
                                     double isovalue, TraceCounters* counters) {
  if (!(double(volume.rootMin()) <= isovalue && isovalue < double(volume.rootMax())))
    return std::nullopt;
  const auto span = clipToBox(ray, Vec3(0.0), Vec3(volume.dataSize() - 1));
  if (!span) return std::nullopt;
  Tracer<T> tracer(volume, ray, isovalue, counters);
  return tracer.run(span->t0, span->t1);
}

template std::optional<VolumeHit> traceOctree(const OctreeVolume<uint8_t>&, const VolumeRay&,
                                              double, TraceCounters*);
template std::optional<VolumeHit> traceOctree(const OctreeVolume<uint16_t>&, const VolumeRay&,
                                              double, TraceCounters*);
template std::optional<VolumeHit> traceOctree(const OctreeVolume<float>&, const VolumeRay&, double,
                                              TraceCounters*);

}  // namespace penumbra::volume
