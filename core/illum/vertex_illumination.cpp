#include "core/illum/vertex_illumination.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/illum/backprojection.h"
#include "core/illum/face_lookup.h"
#include "core/illum/shadow_merge.h"

namespace penumbra {

bool identicalValue(const VertexIrradiance& a, const VertexIrradiance& b) {
  return a.irradiance == b.irradiance && a.lightClass == b.lightClass;
}

bool sameValue(const VertexIrradiance& a, const VertexIrradiance& b) {
  if (a.lightClass != b.lightClass) return false;
  for (int c = 0; c < 3; ++c)
    if (std::abs(a.irradiance[c] - b.irradiance[c]) > 1e-12 * std::max(std::abs(a.irradiance[c]), std::abs(b.irradiance[c])))
      return false;
  return true;
}

namespace {

// One cell's entries for one light.
std::vector<OccluderEntry> entriesFor(const OccluderList& list, size_t light) {
  std::vector<OccluderEntry> out;
  for (const OccluderEntry& e : list)
    if (e.light == light) out.push_back(e);
  return out;
}

// The calling thread's Backprojection, reset for each point: its buffers keep their capacity,
// where a fresh object cost some eight allocations a point. Not reentrant: nothing called
// while a view is in use asks for another.
Backprojection& reusedView(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                           const Vec3& shading) {
  thread_local Backprojection view;
  view.reset(scene, light, p, n, shading);
  return view;
}

VertexLight fromView(const Backprojection& view, VertexCase decidedBy) {
  VertexLight out;
  out.setApplies(true);
  out.setDecidedBy(decidedBy);
  out.setFactor(view.visibleFactor());
  out.setLightClass(view.lightClass());
  out.setComparisons(view.comparisons());
  return out;
}

VertexLight inUmbra() {
  VertexLight out;
  out.setApplies(true);
  out.setDecidedBy(VertexCase::Umbra);
  out.setLightClass(LightClass::Umbra);
  return out;
}

// Sums one light's result into the all-lights result.
void accumulate(VertexIrradiance& total, bool& anyLight, const Light& light,
                const VertexLight& one) {
  if (!one.applies()) return;
  total.irradiance += light.radiance * one.factor();
  total.lightClass = anyLight ? combine(total.lightClass, one.lightClass()) : one.lightClass();
  total.comparisons += one.comparisons();
  anyLight = true;
}

Vec3 directionInPlane(const Vec3& n, const Vec3& d) {
  const Vec3 inPlane = d - glm::dot(n, d) * n;
  const double length = glm::length(inPlane);
  if (!(length > 0)) throw std::invalid_argument("illuminateFromCell: direction along the normal");
  return inPlane / length;
}

}  // namespace

VertexLight illuminateVertex(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                             const Vec3& shading, const std::vector<const OccluderList*>& cellsAround) {
  if (cellsAround.empty()) throw std::invalid_argument("illuminateVertex: no cells around");
  for (const OccluderList* list : cellsAround)
    if (!list) throw std::invalid_argument("illuminateVertex: null occluder list");
  // The lists are read in place, filtered by light: no copy per vertex.
  auto forLight = [&](const OccluderEntry& e) { return e.light == light; };
  auto holdsFace = [&](const OccluderList& list, FaceId face) {
    return std::any_of(list.begin(), list.end(),
                       [&](const OccluderEntry& e) { return e.light == light && e.face == face; });
  };

  Backprojection& view = reusedView(scene, light, p, n, shading);
  if (!view.applies()) return VertexLight{};

  // (1) Some cell sees the whole light, so p does (a blocker of p would block
  // positive area from every cell touching p).
  for (const OccluderList* list : cellsAround)
    if (std::none_of(list->begin(), list->end(), forLight)) return fromView(view, VertexCase::Unoccluded);

  // (2) A face hiding the light from a cell hides it from p too, by continuity,
  // unless its plane contains p (a D⁰ contact): such a face is missing from the
  // cells on its front side, and the rule check below makes it exact. A cell around p
  // may lack it for another reason: umbra culling (DmTree::insert) leaves a cell already
  // in an umbra of this light without the later faces, so such a cell does not count.
  const double onPlane = scene.tolerance().onPlane();
  for (const OccluderList* list : cellsAround)
    for (const OccluderEntry& e : *list) {
      if (!e.umbra) break;  // umbra entries come first
      if (e.light != light) continue;
      // A whole object lies off the receiver's plane (object_shadow.h): never a contact. But
      // a face of it whose plane passes within onPlane() of p hides nothing from p (the
      // single-sided rule), and when it is on the silhouette that leaves a sliver of light
      // the object's umbra does not know of: then backprojection decides, face by face.
      if (isWholeObject(e.face)) {
        if (!mergeableShadows(scene, e.face.object, scene.lights()[light].plane(), p)) continue;
      } else {
        const Face* face = findFace(scene, e.face);
        if (!face || !(face->plane.signedDistance(p) < -onPlane)) continue;
      }
      const bool everywhere = std::all_of(cellsAround.begin(), cellsAround.end(), [&](const OccluderList* other) {
        return holdsFace(*other, e.face) || hasUmbraEntry(*other, uint32_t(light));
      });
      if (everywhere) return inUmbra();
    }

  // (3) O_covering: the faces every cell lists; a face blocking p blocks positive
  // area from each cell around it, so this is a superset of p's blockers.
  // Subtracted in FaceId order: the visible pieces (and their last-bit rounding)
  // then do not depend on the order the cells' lists were built in.
  thread_local std::vector<FaceId> covering;
  covering.clear();
  for (const OccluderEntry& e : *cellsAround.front()) {
    if (e.light != light) continue;
    const bool everywhere = std::all_of(cellsAround.begin() + 1, cellsAround.end(),
                                        [&](const OccluderList* other) { return holdsFace(*other, e.face); });
    if (everywhere) covering.push_back(e.face);
  }
  std::sort(covering.begin(), covering.end());
  for (FaceId id : covering) view.occludeId(id);
  return fromView(view, VertexCase::Covering);
}

VertexIrradiance illuminatePoint(const Scene& scene, const Vec3& p, const Vec3& n, const Vec3& shading,
                                 const std::vector<const OccluderList*>& cellsAround) {
  VertexIrradiance total;
  bool anyLight = false;
  for (size_t l = 0; l < scene.lights().size(); ++l)
    accumulate(total, anyLight, scene.lights()[l], illuminateVertex(scene, l, p, n, shading, cellsAround));
  if (!anyLight) total.lightClass = LightClass::Umbra;
  return total;
}

VertexLight illuminateVertexFromCell(const Scene& scene, size_t light, const Vec3& p,
                                     const Vec3& n, const Vec3& shading, const Vec3& d,
                                     const OccluderList& cell) {
  const Vec3 towards = directionInPlane(n, d);
  const std::vector<OccluderEntry> entries = entriesFor(cell, light);
  Backprojection& view = reusedView(scene, light, p, n, shading);
  if (!view.applies()) return VertexLight{};
  if (entries.empty()) return fromView(view, VertexCase::Unoccluded);
  // The cell's inside is hidden throughout: so is the limit.
  if (entries.front().umbra) return inUmbra();
  std::vector<FaceId> faces;
  for (const OccluderEntry& e : entries) faces.push_back(e.face);
  std::sort(faces.begin(), faces.end());  // order-independent result, as in case (3)
  for (FaceId id : faces) {
    if (isWholeObject(id)) {
      view.occludeObject(id.object, &towards);  // a mesh on its own face: its faces' limits at p
    } else if (const Face* face = findFace(scene, id)) {
      view.occludeApproaching(*face, towards);
    }
  }
  return fromView(view, VertexCase::Covering);
}

VertexIrradiance illuminatePointFromCell(const Scene& scene, const Vec3& p, const Vec3& n,
                                         const Vec3& shading, const Vec3& d, const OccluderList& cell) {
  VertexIrradiance total;
  bool anyLight = false;
  for (size_t l = 0; l < scene.lights().size(); ++l)
    accumulate(total, anyLight, scene.lights()[l],
               illuminateVertexFromCell(scene, l, p, n, shading, d, cell));
  if (!anyLight) total.lightClass = LightClass::Umbra;
  return total;
}

}  // namespace penumbra
