// The visible part of one light from one point, given candidate occluder faces:
// the light clipped to the point's front half-space minus the central projections
// of the faces that block the point (SCENE_FORMAT.md rule), and its Lambert integral.
// Shadows are gathered; the integral is Lambert's edge sum over the boundary of what
// they leave (VisibleContour), the pieces are formed only when asked for (largest
// shadow first). One object per (light, point), one thread.
#pragma once

#include <cstddef>
#include <span>
#include <utility>
#include <vector>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"
#include "core/illum/light_class.h"
#include "core/illum/shadow_chain.h"
#include "core/illum/visible_contour.h"
#include "core/illum/visible_region.h"
#include "core/scene/scene.h"

namespace penumbra {

class Backprojection {
 public:
  // Light `light` of `scene` seen from p with unit front normal n, nothing removed yet.
  // `shading` (unit, in front of n's plane; shading_normal.h) is the normal the factors are
  // taken about: Lambert's integral of cos⁺ about it over what is visible. n alone decides
  // visibility (the front part, the single-sided rule, what blocks).
  Backprojection(const Scene& scene, size_t light, const Vec3& p, const Vec3& n);
  Backprojection(const Scene& scene, size_t light, const Vec3& p, const Vec3& n, const Vec3& shading);
  Backprojection() = default;  // applies() is false until reset()
  // Starts afresh as the constructor would, keeping the buffers' capacity: one object
  // reused for many points allocates nothing once warm (vertex_illumination.cpp).
  void reset(const Scene& scene, size_t light, const Vec3& p, const Vec3& n) { reset(scene, light, p, n, n); }
  void reset(const Scene& scene, size_t light, const Vec3& p, const Vec3& n, const Vec3& shading);

  // Whether the light faces p (p strictly in front of its plane) and some of it lies
  // in front of p's plane; otherwise it contributes nothing and has no class.
  bool applies() const { return applies_; }

  // Removes the projection of `face` if it can block p: p lies more than onPlane()
  // behind its plane and part of it lies between p and the light, inside the cone
  // from p over the light. Returns whether it was projected (one source/occluder
  // comparison); the subtraction happens when a result is asked for. The result
  // depends on the set of faces given and not on their order.
  bool occlude(const Face& face);

  // Removes what a whole closed convex object hides from p (an occluder list's
  // wholeObject() entry, core/shadow/object_shadow.h): when its shadows merge
  // (shadow_merge.h) and it lies wholly in front of p's plane and well between p and the
  // light, the hull of the projected corners of the faces p is behind (they tile the
  // object's projection); otherwise its faces one by one, as occlude(). One comparison.
  // With `towards` (unit, in p's plane), a mesh's faces whose plane contains p count as
  // occludeApproaching() does: the limit as the point tends to p from that direction (a
  // mesh on its own face, where a face in front of it meets it).
  bool occludeObject(uint32_t handle, const Vec3* towards = nullptr);
  // Any other object with a mesh (Scene::meshTopology): the projections of its blocking
  // faces whose corners all lie ahead of p's plane and between p and the light (1e-3 of
  // p's height short of it) as one chain (shadow_chain.h). A blocking face the chain cannot
  // hold goes one by one, as occlude(), and so does every chain face joined to it through
  // faces sharing a corner (splitOffAlone); with `towards`, a face whose plane holds p that
  // blocks as p is approached sends every face one by one.
  //
  // occlude() for a face's id, occludeObject() for a wholeObject() id; ids not in the
  // scene are ignored.
  bool occludeId(FaceId id);

  // The same for the limit as the point tends to p from direction d (unit, in p's
  // plane): a face whose plane contains p blocks iff p + δd is behind it, and then
  // hides the light points q in front of its plane whose segment from p + δd
  // crosses it as δ → 0 (p on the face, q − p entering it). Other faces as occlude().
  bool occludeApproaching(const Face& face, const Vec3& d);

  // ∫ cos⁺θs·cosθL / r² dA over the front part of the light, and over what is left, with
  // θs the angle to the shading normal (n itself unless one was given).
  double unoccludedFactor() const;
  double visibleFactor() const;
  // Some candidate removed positive area; some positive area is left.
  bool occluded() const {
    resolve();
    return occluded_;
  }
  bool anyVisible() const;
  // Lit (nothing removed), Umbra (nothing left) or Penumbra; Lit if !applies().
  LightClass lightClass() const;
  size_t comparisons() const { return comparisons_; }
  // The visible part in world space (on the light's plane), convex pieces: what n's point
  // sees, not clipped to the shading normal's front.
  std::vector<Polygon3> visiblePieces() const;

 private:
  void subtractShadow(const Polygon3& onLightPlane, uint32_t group);
  // The shadow already in the light's frame (appended as it is: counter-clockwise).
  void subtractShadow2D(std::span<const Vec2> shadow, uint32_t group);
  // The merge group of an object's shadows (its handle, or kNoGroup; shadow_merge.h).
  uint32_t groupOf(uint32_t object);
  const uint32_t* decidedGroup(uint32_t object) const;  // groupOf()'s answer for this point, if decided
  // Each face occluded alone; whether any blocks p.
  bool occludeFaces(std::span<const Face> faces);
  // The gathered shadows with each object's group merged: the given buffers, or the
  // gathered ones when nothing merges.
  bool mergedShadows(std::vector<Vec2>& points, std::vector<uint32_t>& starts) const;
  // The boundary of what the gathered shadows leave and its Lambert integral, once
  // per set of shadows.
  void resolve() const;
  // The visible part as convex pieces: the shadows subtracted, largest first.
  void resolvePieces(VisibleRegion& region) const;
  double cutEps() const;
  // Lambert's sum about the shading normal over `boundary` clipped to its front half-space.
  double shadedBoundarySum(std::span<const Segment2> boundary) const;
  bool occludeMesh(uint32_t handle, const MeshTopology& mesh, std::span<const Face> faces, const Vec3* towards);
  // occludeMesh's faces that block p one by one (`alone`, already subtracted): each chain face
  // joined to them through chain or alone faces sharing a corner is subtracted one by one too
  // and leaves the chain (chainFaces, chainClusters: a cluster losing a face is listed face by
  // face); `alone` grows by those.
  void splitOffAlone(const MeshTopology& mesh, std::span<const Face> faces, std::vector<uint32_t>& chainFaces,
                     std::vector<uint32_t>& chainClusters, std::vector<uint32_t>& alone);
  // occlude() short of subtracting: the face's part that blocks p, projected onto the light's
  // plane, into blocker_; false when no part of it blocks p.
  bool projectBlocker(const Face& face) const;
  // The face lies wholly outside a side of the cone from p over the light's front part (by more
  // than a length tolerance): its shadow misses the light, whatever projectBlocker() says (its
  // cone is widened by the light's size, so that it keeps such shadows whole).
  bool besideLight(const Face& face);
  // The mesh's chain of the given blocking faces into chain_ (appendShadowChain).
  bool appendChain(uint32_t handle, const MeshTopology& mesh, std::span<const uint32_t> faces,
                   std::span<const uint32_t> clusters, std::span<const std::pair<uint32_t, int>> summedEdges);
  // Inward side planes of the cone from p over front_ (no margin), made on first use.
  const std::vector<Plane>& lightCone();
  // cone_, made on first use: only a face projected one by one is clipped by it (a closed
  // convex object's hull and a refinement point's level need none).
  const std::vector<Plane>& clipCone() const;

  const Scene* scene_ = nullptr;
  Tolerance tolerance_;
  Vec3 p_{0.0}, n_{0.0};
  Vec3 s_{0.0};                 // the shading normal
  bool smooth_ = false;         // s_ differs from n_
  Polygon3 lightPolygon_;       // the light's polygon that lightPlane_ and frame_ are of
  Plane lightPlane_;
  double pHeight_ = 0;          // p's distance in front of the light's plane
  bool applies_ = false;
  Polygon3 front_;              // the light clipped to p's front half-space
  PlaneFrame frame_;            // 2D frame on the light's plane (set even when !applies_)
  mutable std::vector<Plane> cone_;  // inward side planes of a cone from p over front_ plus a margin
  mutable bool coneMade_ = false;    // cone_ made for this p (clipCone())
  std::vector<Plane> lightCone_;  // lightCone(), empty until asked for
  Polygon2 front2_;             // front_ in the frame, CCW
  std::vector<Vec2> shadowPoints_;      // gathered shadows in the frame, flat, CCW
  std::vector<uint32_t> shadowStarts_;  // shadow i: [starts[i], starts[i+1])
  std::vector<uint32_t> shadowGroups_;  // shadow i's merge group
  std::vector<std::pair<uint32_t, uint32_t>> groups_;  // (object, group) decided so far
  std::vector<ChainEdge> chain_;        // meshes' shadows as one chain, in the frame
  std::vector<uint32_t> chainObjects_;  // the meshes in chain_
  bool meshFacesAlone_ = false;         // a mesh's faces went one by one: its shadows share edges
  // Resolved state (filled lazily by resolve(); one thread owns the object).
  mutable bool resolved_ = false;
  mutable bool occluded_ = false, anyVisible_ = false;
  mutable double visibleFactor_ = 0;
  mutable Polygon3 blocker_, scratch_;  // reused clipping buffers
  size_t comparisons_ = 0;
};

// One-shot form: the light from p minus the candidate faces (ids not in the scene
// are ignored).
struct LightVisibleFactor {
  bool applies = false;
  double unoccludedFactor = 0;
  double visibleFactor = 0;
  LightClass lightClass = LightClass::Lit;
  size_t comparisons = 0;
};
LightVisibleFactor backproject(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                               std::span<const FaceId> candidates);

}  // namespace penumbra
