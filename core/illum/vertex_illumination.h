// Illuminating a DM-mesh vertex from the occluder lists of the cells around it
// (paper §2.4, its three cases made exact), and the one-sided limit from one cell
// for vertices on value discontinuities. Free functions on a const Scene; thread-safe.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "core/dmtree/occluder_list.h"
#include "core/illum/light_class.h"
#include "core/scene/scene.h"

namespace penumbra {

// Which of §2.4's cases decided a vertex's value for one light.
enum class VertexCase : uint8_t {
  NoLight,     // the light does not face p or lies wholly behind p's plane
  Unoccluded,  // (1) some cell has no occluder for the light
  Umbra,       // (2) one face hides the whole light from every cell and from p
  Covering,    // (3) backprojection of the faces common to all the cells
};

// One light at a vertex.
// 12 bytes: one is kept per vertex and light (PerLightValues). The factor is kept as two 32-bit
// words, read and written by value, so the type needs no packing: no member sits misaligned and no
// reference to one can be taken (a reference to a packed double was undefined behaviour). The
// factor over the light's whole front part (Backprojection::unoccludedFactor) is not kept:
// nothing reads it once the vertex is lit.
class VertexLight {
 public:
  static constexpr uint32_t kMaxComparisons = (1u << 24) - 1;  // counts saturate there

  // ∫ cosθp·cosθL / r² dA over the visible part.
  double factor() const {
    double f;
    std::memcpy(&f, factorWords_, sizeof f);
    return f;
  }
  void setFactor(double f) { std::memcpy(factorWords_, &f, sizeof f); }
  // Source/occluder comparisons (faces projected), saturating at kMaxComparisons.
  uint32_t comparisons() const { return comparisons_; }
  void setComparisons(size_t n) { comparisons_ = uint32_t(std::min<size_t>(n, kMaxComparisons)); }
  // Meaningless when !applies().
  LightClass lightClass() const { return lightClass_; }
  void setLightClass(LightClass c) { lightClass_ = c; }
  // The light reaches p's front side at all.
  bool applies() const { return applies_; }
  void setApplies(bool a) { applies_ = a; }
  VertexCase decidedBy() const { return decidedBy_; }
  void setDecidedBy(VertexCase c) { decidedBy_ = c; }

 private:
  uint32_t factorWords_[2] = {0, 0};  // the factor's bytes (0.0)
  uint32_t comparisons_ : 24 = 0;
  LightClass lightClass_ : 2 = LightClass::Lit;
  bool applies_ : 1 = false;
  VertexCase decidedBy_ : 2 = VertexCase::NoLight;
};
static_assert(sizeof(VertexLight) == 12 && alignof(VertexLight) == 4);

// All lights at a vertex: radiance-weighted sum and combined class (Umbra when no
// light applies, as for the reference).
// 32 bytes: one is kept per vertex.
struct VertexIrradiance {
  Vec3 irradiance{0.0};
  uint32_t comparisons = 0;
  LightClass lightClass = LightClass::Umbra;
};
static_assert(sizeof(VertexIrradiance) == 32);

// Bit for bit the same irradiance and class (the mesh memo's test).
bool identicalValue(const VertexIrradiance& a, const VertexIrradiance& b);
// The same class and each channel within 1e-12 relative: what counts as a changed
// value for relight counters (a vertex lit again from other cells may move the last bits).
bool sameValue(const VertexIrradiance& a, const VertexIrradiance& b);

// Light `light` at p (unit front normal n, shaded about `shading`: n itself for a flat face;
// Backprojection) from the occluder lists of the cells
// around p (entries of other lights are ignored). The cases in order:
// (1) a cell without entry for the light → the whole front part, Lit;
// (2) a face flagged umbra in some cell, present in every cell and blocking p under
//     the single-sided rule → 0, Umbra (a D⁰ vertex's umbra face misses the cells
//     on its other side, or contains p, so such a vertex falls through);
// (3) the faces present in every cell → backprojection; Penumbra if something was
//     removed, Umbra if nothing is left, Lit otherwise.
// Throws std::invalid_argument if cellsAround is empty or holds a null list.
VertexLight illuminateVertex(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                             const Vec3& shading, const std::vector<const OccluderList*>& cellsAround);
VertexIrradiance illuminatePoint(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& shading,
                                 const std::vector<const OccluderList*>& cellsAround);

// The limit of the same quantity as the point tends to p from inside `cell`, along
// direction d (projected into p's plane; must not be along n): no entry → Lit; a
// face flagged umbra → 0, Umbra; otherwise the cell's faces, a face whose plane
// contains p blocking by its limiting projection (Backprojection::occludeApproaching).
VertexLight illuminateVertexFromCell(const Scene& scene, size_t light, const Vec3& p,
                                     const Vec3& n, const Vec3& shading, const Vec3& d,
                                     const OccluderList& cell);
VertexIrradiance illuminatePointFromCell(const Scene& scene, const Vec3& p, const Vec3& n,
                                         const Vec3& shading, const Vec3& d, const OccluderList& cell);

}  // namespace penumbra
