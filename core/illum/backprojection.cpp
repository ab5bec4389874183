#include "core/illum/backprojection.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "core/geom/clip.h"
#include "core/illum/face_lookup.h"
#include "core/illum/lambert.h"
#include "core/illum/mesh_box_chain.h"
#include "core/illum/shadow_merge.h"
#include "core/illum/visible_contour.h"
#include "core/scene/convex_solid.h"
#include "core/scene/mesh_topology.h"
#include "core/util/stamped_set.h"

namespace penumbra {

Backprojection::Backprojection(const Scene& scene, size_t light, const Vec3& p, const Vec3& n) {
  reset(scene, light, p, n, n);
}

Backprojection::Backprojection(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                               const Vec3& shading) {
  reset(scene, light, p, n, shading);
}

void Backprojection::reset(const Scene& scene, size_t light, const Vec3& p, const Vec3& n, const Vec3& shading) {
  scene_ = &scene;
  tolerance_ = scene.tolerance();
  p_ = p;
  n_ = n;
  s_ = shading;
  smooth_ = shading != n;
  applies_ = false;
  front_.clear();
  cone_.clear();
  coneMade_ = false;
  lightCone_.clear();
  front2_.clear();
  shadowPoints_.clear();
  shadowStarts_.clear();
  shadowGroups_.clear();
  groups_.clear();
  chain_.clear();
  chainObjects_.clear();
  resolved_ = occluded_ = anyVisible_ = false;
  meshFacesAlone_ = false;
  visibleFactor_ = 0;
  comparisons_ = 0;

  const Light& source = scene.lights().at(light);
  const double eps = tolerance_.length();
  // The light's plane and frame depend on its polygon alone: a reused object keeps them
  // while the polygon is the same (Newell's normal per point was ~1% of a build).
  // Compared bit for bit (+0 and -0 differ), and kept only once the plane was found.
  const bool sameLight = lightPolygon_.size() == source.polygon.size() &&
                         std::memcmp(lightPolygon_.data(), source.polygon.data(), source.polygon.size() * sizeof(Vec3)) == 0;
  if (!sameLight) {
    lightPolygon_.clear();
    lightPlane_ = source.plane();
    frame_ = PlaneFrame::onPlane(lightPlane_, source.polygon[0]);
    lightPolygon_ = source.polygon;
  }
  // The light emits from its front only: p must be strictly in front of it.
  pHeight_ = lightPlane_.signedDistance(p);
  if (!(pHeight_ > eps)) return;
  // As withoutDuplicateVertices(clipFront(...)), into the kept buffers.
  clipFrontInto(source.polygon, Plane::throughPoint(n, p), eps, scratch_);
  for (const Vec3& v : scratch_)
    if (front_.empty() || glm::length(v - front_.back()) > eps) front_.push_back(v);
  while (front_.size() > 1 && glm::length(front_.front() - front_.back()) <= eps) front_.pop_back();
  if (front_.size() < 3) return;
  applies_ = true;

  for (const Vec3& q : front_) front2_.push_back(frame_.to2D(q));
  if (signedArea(front2_) < 0) std::reverse(front2_.begin(), front2_.end());  // counter-clockwise
  shadowStarts_.push_back(0);
}

const std::vector<Plane>& Backprojection::clipCone() const {
  if (coneMade_ || front_.size() < 3) return cone_;
  coneMade_ = true;
  const Vec3& p = p_;  // the apex
  // Side planes of the cone from p over the front part with every edge moved out,
  // in the light's plane, by the front part's own size. The cone only keeps the
  // projections finite; the exact trim is the 2D subtraction against the light.
  // The margin must be large, not a few eps: clipping a blocker at a boundary just
  // outside the light leaves it short edges (~eps long, magnified) along its real
  // edges, and the 2D subtraction cuts the light along their lines, whose
  // directions they fix only to rounding / length. Extended across the light such
  // a cut lands ~1e-9 of the light's size off the true edge, and the next shadow
  // through the same edge (its neighbour face) cannot snap it back: area lost.
  // With the boundary this far out, blocker vertices within eps of it are far
  // outside the light too, so no sliver of the light is ever left uncovered.
  const Vec3 inner = centroid(front_);
  Vec3 low = front_[0], high = front_[0];
  for (const Vec3& q : front_) {
    low = glm::min(low, q);
    high = glm::max(high, q);
  }
  const double margin = glm::length(high - low);
  for (size_t i = 0; i < front_.size(); ++i) {
    const Vec3 a = front_[i], b = front_[(i + 1) % front_.size()];
    Vec3 out = glm::cross(b - a, lightPlane_.normal);
    const double outLength = glm::length(out);
    if (!(outLength > 0)) continue;
    out /= outLength;
    if (glm::dot(out, inner - a) > 0) out = -out;
    const Vec3 normal = glm::cross(a + margin * out - p, b + margin * out - p);
    const double length = glm::length(normal);
    if (!(length > 0)) continue;
    const Vec3 unit = (glm::dot(normal, inner - p) < 0 ? -normal : normal) / length;
    cone_.push_back(Plane::throughPoint(unit, p));
  }
  return cone_;
}

bool Backprojection::occlude(const Face& face) {
  if (!projectBlocker(face)) return false;
  subtractShadow(blocker_, groupOf(face.id.object));
  return true;
}

namespace {

// Every corner of `polygon` more than eps outside one of the inward `sides` (so all of it is).
bool outsideASide(const Polygon3& polygon, std::span<const Plane> sides, double eps) {
  return std::any_of(sides.begin(), sides.end(), [&](const Plane& side) {
    return std::all_of(polygon.begin(), polygon.end(), [&](const Vec3& v) { return side.signedDistance(v) < -eps; });
  });
}

}  // namespace

bool Backprojection::besideLight(const Face& face) {
  return outsideASide(face.polygon, lightCone(), tolerance_.length());
}

bool Backprojection::projectBlocker(const Face& face) const {
  if (!applies_) return false;
  // The single-sided rule: only faces p is strictly behind can block it.
  if (!(face.plane.signedDistance(p_) < -tolerance_.onPlane())) return false;

  // Cheap rejects: a blocking point lies in front of p's plane and strictly
  // between p and the light's plane.
  const Plane receiver = Plane::throughPoint(n_, p_);
  bool ahead = false, beforeLight = false, beyondP = false;
  for (const Vec3& v : face.polygon) {
    ahead |= receiver.signedDistance(v) > 0;
    const double h = lightPlane_.signedDistance(v);
    beforeLight |= h > 0;
    beyondP |= h < pHeight_;
  }
  if (!ahead || !beforeLight || !beyondP) return false;
  // Wholly outside a side of the cone: every part of it is, and that clip leaves nothing
  // (most faces asked of a point near a model lie beside its cone).
  const double eps = tolerance_.length();
  const std::vector<Plane>& cone = clipCone();
  if (outsideASide(face.polygon, cone, eps)) return false;

  // Keep the part between p and the light inside the cone; the cap just short of
  // p's height keeps the projection finite (a blocking face is ≥ onPlane from p).
  // Clipped back and forth between two reused buffers.
  Polygon3& blocker = blocker_;
  clipFrontInto(face.polygon, lightPlane_, eps, blocker);
  const Plane cap{-lightPlane_.normal, -lightPlane_.offset + pHeight_ - 2 * eps};
  if (blocker.size() >= 3) {
    clipFrontInto(blocker, cap, eps, scratch_);
    std::swap(blocker, scratch_);
  }
  for (const Plane& side : cone) {
    if (blocker.size() < 3) break;
    clipFrontInto(blocker, side, eps, scratch_);
    std::swap(blocker, scratch_);
  }
  if (blocker.size() < 3) return false;

  // Central projection from p onto the light's plane: along the ray p→x the
  // height above the light falls linearly from pHeight to 0.
  for (Vec3& x : blocker) x = p_ + (x - p_) * (pHeight_ / (pHeight_ - lightPlane_.signedDistance(x)));
  return true;
}

bool Backprojection::occludeApproaching(const Face& face, const Vec3& d) {
  if (!applies_) return false;
  const double onPlane = tolerance_.onPlane();
  const double distance = face.plane.signedDistance(p_);
  if (distance < -onPlane) return occlude(face);  // continuous at p
  if (distance > onPlane) return false;
  const Vec3 nF = face.plane.normal;
  // p + δd must be behind the face; a direction along its plane stays on it.
  const double nd = glm::dot(nF, d);
  if (!(nd < -tolerance_.length() / tolerance_.sceneSize)) return false;

  // The crossing point of (p + δd → q) with the face's plane tends to p along
  // w = d + (−n·d / n·(q−p)) (q−p), so it lies in the face iff p does and w points
  // into the face at p: for every edge through p with inward normal m, m·w > 0,
  // i.e. ((m·d) n − (n·d) m) · (q − p) > 0 (multiplied by n·(q−p) > 0).
  const PlaneFrame faceFrame = PlaneFrame::onPlane(face.plane, p_);  // p at its origin
  Polygon2 outline;
  outline.reserve(face.polygon.size());
  for (const Vec3& v : face.polygon) outline.push_back(faceFrame.to2D(v));
  outline = counterClockwise(std::move(outline));
  std::vector<Plane> hides{Plane::throughPoint(nF, p_)};  // q in front of the face
  const Vec2 origin{0.0};
  for (size_t i = 0; i < outline.size(); ++i) {
    const Vec2 a = outline[i], b = outline[(i + 1) % outline.size()];
    const double side = lineDistance(a, b, origin);
    if (side < -onPlane) return false;  // p is off the face
    if (side > onPlane || a == b) continue;
    const Vec2 inward2 = glm::normalize(Vec2(a.y - b.y, b.x - a.x));
    const Vec3 m = inward2.x * faceFrame.u + inward2.y * faceFrame.v;
    const Vec3 normal = glm::dot(m, d) * nF - nd * m;  // never zero: nd ≠ 0, m ⟂ nF
    hides.push_back(Plane::throughPoint(glm::normalize(normal), p_));
  }

  const double eps = tolerance_.length();
  Polygon3 hidden = front_;
  for (const Plane& plane : hides) {
    hidden = clipFront(hidden, plane, eps);
    if (hidden.size() < 3) return false;
  }
  subtractShadow(hidden, kNoGroup);
  return true;
}

bool Backprojection::occludeMesh(uint32_t handle, const MeshTopology& mesh, std::span<const Face> faces,
                                 const Vec3* towards) {
  // Faces whose corners all lie ahead of p's plane and between p and the light (1e-3 of
  // p's height short of it) project with one orientation: they go into the chain. Where
  // another face (near p's height, or reaching behind p's plane) blocks p, it is projected
  // one by one, and so is every chain face joined to it through faces sharing a corner: its
  // shadow would otherwise share edges or corners with the chain's, and only the convex
  // contour decides edges along each other consistently (splitOffAlone). Faces in clusters
  // outside the cone from p over the light block nothing and are not looked at.
  const Plane receiver = Plane::throughPoint(n_, p_);
  const ConvexSolid& w = mesh.welded;
  enum : uint8_t { kUsable = 1, kAhead = 2, kBeyondLight = 4, kBeforeP = 8 };
  thread_local StampedMemo<uint8_t> corner;  // kUsable, kAhead, kBeyondLight, kBeforeP
  thread_local std::vector<uint32_t> chainFaces, chainClusters, aloneFaces;
  corner.clear(w.vertices.size());
  auto flags = [&](uint32_t v) {
    return corner.value(v, [&](uint32_t) {
      const double h = lightPlane_.signedDistance(w.vertices[v]);
      const bool ahead = receiver.signedDistance(w.vertices[v]) > 0;
      return uint8_t((ahead && h > 0 && pHeight_ - h > 1e-3 * pHeight_ ? kUsable : 0) | (ahead ? kAhead : 0) |
                     (h > 0 ? kBeyondLight : 0) | (h < pHeight_ ? kBeforeP : 0));
    });
  };
  // A face p is behind: in the chain (every corner usable), projected alone (a corner ahead
  // of p's plane, one beyond the light's and one short of p's height), or blocking nothing.
  enum class Decision { kChain, kAlone, kNone };
  auto decide = [&](uint32_t f) {
    uint8_t all = 0xff, any = 0;
    for (uint32_t k = w.faceStarts[f]; k < w.faceStarts[f + 1]; ++k) {
      const uint8_t c = flags(w.corners[k]);
      all &= c;
      any |= c;
    }
    if (all & kUsable) return Decision::kChain;
    constexpr uint8_t kMayBlock = kAhead | kBeyondLight | kBeforeP;
    return (any & kMayBlock) == kMayBlock ? Decision::kAlone : Decision::kNone;
  };
  const double onPlane = tolerance_.onPlane();
  chainFaces.clear();
  chainClusters.clear();
  // A point of a box over which the whole mesh is usable: the faces behind all of the box
  // come summed, the point decides those whose plane crosses it (mesh_box_chain.h).
  const MeshBoxChain* box = towards ? nullptr : meshBoxChain(mesh, p_, n_, lightPolygon_, lightPlane_, tolerance_);
  if (box && box->usable) {
    for (const uint32_t i : box->crossing)
      if (mesh.clusterPlanes[i].signedDistance(p_) < -onPlane) chainFaces.push_back(mesh.clusterFaces[i]);
    // Special faces as the loop below decides them; one that blocks p on its own sends p to
    // that loop (it and the faces joined to it one by one), which projects it again.
    bool alone = false;
    for (const uint32_t i : box->special) {
      if (!(mesh.clusterPlanes[i].signedDistance(p_) < -onPlane)) continue;
      const uint32_t f = mesh.clusterFaces[i];
      const Decision decision = decide(f);
      if (decision == Decision::kChain) chainFaces.push_back(f);
      alone = decision == Decision::kAlone && !besideLight(faces[f]) && projectBlocker(faces[f]);
      if (alone) break;
    }
    if (!alone) return appendChain(handle, mesh, chainFaces, {}, box->behindAll);
    chainFaces.clear();
  }
  const std::vector<Plane>& sides = lightCone();
  auto missesCone = [&](const MeshTopology::Cluster& c) {
    const double r = c.radius + tolerance_.length(), h = lightPlane_.signedDistance(c.centre);
    if (receiver.signedDistance(c.centre) < -r || h < -r || h > pHeight_ + r) return true;
    return std::any_of(sides.begin(), sides.end(), [&](const Plane& side) { return side.signedDistance(c.centre) < -r; });
  };
  // A ball wholly ahead of p's plane, beyond the light's and short of p's height with the
  // margin of kUsable (and a length tolerance more) holds only usable corners: its faces need
  // no corner looked at.
  auto wholeUsable = [&](const MeshTopology::Cluster& c) {
    const double r = c.radius + tolerance_.length(), h = lightPlane_.signedDistance(c.centre);
    return receiver.signedDistance(c.centre) > r && h > r && pHeight_ - (h + r) > 1e-3 * pHeight_;
  };
  // In the chain: faces p is strictly behind (blocking ones) with every corner usable.
  // Faces whose plane holds p count only as limits (with `towards`); the rest go one by
  // one, but for those with no corner ahead of p's plane, past the light's or short of p's
  // height, which cannot block (occlude() would say so).
  bool approachBlocks = false;
  aloneFaces.clear();
  mesh.forEachClusterMeeting(missesCone, [&](uint32_t c) {
    const MeshTopology::Cluster& cluster = mesh.clusters[c];
    const bool usable = wholeUsable(cluster);
    const size_t before = chainFaces.size();
    for (uint32_t i = cluster.first; i < cluster.last; ++i) {
      const uint32_t f = mesh.clusterFaces[i];
      const double distance = mesh.clusterPlanes[i].signedDistance(p_);
      if (!(distance < -onPlane)) {
        if (towards && !(distance > onPlane)) approachBlocks = occludeApproaching(faces[f], *towards) || approachBlocks;
        continue;
      }
      if (usable) {
        chainFaces.push_back(f);
        continue;
      }
      const Decision decision = decide(f);
      if (decision == Decision::kChain) chainFaces.push_back(f);
      else if (decision == Decision::kAlone && !besideLight(faces[f]) && occlude(faces[f])) aloneFaces.push_back(f);
    }
    // Every face of the cluster in the chain: its precomputed sum stands for them.
    if (chainFaces.size() - before == size_t(cluster.last - cluster.first)) {
      chainFaces.resize(before);
      chainClusters.push_back(c);
    }
    return true;
  });
  if (approachBlocks) {
    meshFacesAlone_ = true;
    for (uint32_t c : chainClusters)
      for (uint32_t i = mesh.clusters[c].first; i < mesh.clusters[c].last; ++i) occlude(faces[mesh.clusterFaces[i]]);
    for (uint32_t f : chainFaces) occlude(faces[f]);
    return true;
  }
  if (aloneFaces.empty()) return appendChain(handle, mesh, chainFaces, chainClusters, {});
  meshFacesAlone_ = true;
  splitOffAlone(mesh, faces, chainFaces, chainClusters, aloneFaces);
  appendChain(handle, mesh, chainFaces, chainClusters, {});
  return true;
}

void Backprojection::splitOffAlone(const MeshTopology& mesh, std::span<const Face> faces,
                                   std::vector<uint32_t>& chainFaces, std::vector<uint32_t>& chainClusters,
                                   std::vector<uint32_t>& alone) {
  // The faces projected alone (already subtracted) and every chain face joined to them through
  // chain or alone faces sharing a corner: those go one by one too, so no chain edge or corner
  // inside the light is also a corner of a convex shadow (the contour decides edges along each
  // other only between convex shadows). A face wholly beside the light (besideLight: its
  // projection lies outside it) stops the spread: what it shares projects outside the light,
  // where neither the contour nor the chain's winding is looked at. The rest stays one chain,
  // as a mesh's chain beside other objects' shadows.
  thread_local StampedSet inChain, inAlone;  // a face in both: alone
  inChain.clear(faces.size()), inAlone.clear(faces.size());
  for (uint32_t f : chainFaces) inChain.insert(f);
  for (uint32_t c : chainClusters)
    for (uint32_t i = mesh.clusters[c].first; i < mesh.clusters[c].last; ++i) inChain.insert(mesh.clusterFaces[i]);
  for (uint32_t f : alone) inAlone.insert(f);
  const ConvexSolid& w = mesh.welded;
  for (size_t next = 0; next < alone.size(); ++next) {
    const uint32_t f = alone[next];
    for (uint32_t k = w.faceStarts[f]; k < w.faceStarts[f + 1]; ++k) {
      const uint32_t v = w.corners[k];
      for (uint32_t j = mesh.vertexStarts[v]; j < mesh.vertexStarts[v + 1]; ++j) {
        const uint32_t g = mesh.vertexFaces[j];
        // A face wholly beside the light shares only what projects outside it with the faces
        // around it: no chain edge or corner inside the light meets a convex shadow's there.
        if (!inChain.contains(g) || inAlone.contains(g) || besideLight(faces[g])) continue;
        inAlone.insert(g);
        occlude(faces[g]);
        alone.push_back(g);
      }
    }
  }
  std::erase_if(chainFaces, [&](uint32_t f) { return inAlone.contains(f); });
  // A cluster with a face gone alone is no longer whole: its other faces join the chain's list.
  std::erase_if(chainClusters, [&](uint32_t c) {
    const auto& cluster = mesh.clusters[c];
    const bool broken = std::any_of(mesh.clusterFaces.begin() + cluster.first, mesh.clusterFaces.begin() + cluster.last,
                                    [&](uint32_t f) { return inAlone.contains(f); });
    if (broken)
      for (uint32_t i = cluster.first; i < cluster.last; ++i)
        if (!inAlone.contains(mesh.clusterFaces[i])) chainFaces.push_back(mesh.clusterFaces[i]);
    return broken;
  });
}

bool Backprojection::appendChain(uint32_t handle, const MeshTopology& mesh, std::span<const uint32_t> faces,
                                 std::span<const uint32_t> clusters,
                                 std::span<const std::pair<uint32_t, int>> summedEdges) {
  ++comparisons_;
  if (!appendShadowChain(mesh, faces, clusters, summedEdges, p_, lightPlane_, pHeight_, frame_, tolerance_.area(),
                         chain_))
    return false;
  chainObjects_.push_back(handle);
  resolved_ = false;
  return true;
}

const std::vector<Plane>& Backprojection::lightCone() {
  if (!lightCone_.empty() || front_.size() < 3) return lightCone_;
  const Vec3 inner = centroid(front_);
  for (size_t i = 0; i < front_.size(); ++i) {
    const Vec3 normal = glm::cross(front_[i] - p_, front_[(i + 1) % front_.size()] - p_);
    const double length = glm::length(normal);
    if (!(length > 0)) continue;
    lightCone_.push_back(Plane::throughPoint((glm::dot(normal, inner - p_) < 0 ? -normal : normal) / length, p_));
  }
  return lightCone_;
}

bool Backprojection::occludeObject(uint32_t handle, const Vec3* towards) {
  if (!applies_) return false;
  const std::span<const Face> faces = scene_->facesOfObject(handle);
  const ConvexSolid* convex = scene_->convexSolid(handle);
  if (!convex) {
    if (const MeshTopology* mesh = scene_->meshTopology(handle)) return occludeMesh(handle, *mesh, faces, towards);
    return occludeFaces(faces);
  }
  // The hull needs the merge's conditions (closed convex, wholly in front of the light, p
  // off every face's plane) and every corner ahead of p's plane, with a height below p's
  // that keeps the projection within 1000 times the corner's distance. Each corner's height
  // and each face's side of p are found once here for all three (as mergeableShadows()
  // finds them; a clutter's evaluation asks this of every box in its list).
  thread_local std::vector<double> heights;
  thread_local std::vector<uint8_t> seenBy, faceSide;
  const ConvexSolid& solid = *convex;
  const double onPlane = tolerance_.onPlane();
  bool mergeable = true;
  heights.resize(solid.vertices.size());
  for (size_t i = 0; i < solid.vertices.size(); ++i) {
    heights[i] = lightPlane_.signedDistance(solid.vertices[i]);
    mergeable = mergeable && mergeableCorner(heights[i], tolerance_);
  }
  faceSide.resize(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    const double side = faces[f].plane.signedDistance(p_);
    mergeable = mergeable && mergeableFaceSide(side, tolerance_);
    faceSide[f] = side < -onPlane ? 1 : 2;  // 1: p behind the face (it blocks p)
  }
  if (!decidedGroup(handle)) groups_.push_back({handle, mergeable ? handle : kNoGroup});
  const Plane receiver = Plane::throughPoint(n_, p_);
  bool hull = mergeable;
  for (size_t i = 0; hull && i < solid.vertices.size(); ++i)
    hull = receiver.signedDistance(solid.vertices[i]) > 0 && pHeight_ - heights[i] > 1e-3 * pHeight_;
  if (!hull) return occludeFaces(faces);
  // The outline of the projection: corners of a face that blocks p (p behind it) and of
  // one that does not, i.e. on the silhouette seen from p (every face is one or the other).
  thread_local std::vector<Vec2> corners, outline;
  seenBy.assign(solid.vertices.size(), 0);
  for (size_t f = 0; f < faces.size(); ++f)
    for (uint32_t k = solid.faceStarts[f]; k < solid.faceStarts[f + 1]; ++k) seenBy[solid.corners[k]] |= faceSide[f];
  corners.clear();
  for (size_t i = 0; i < solid.vertices.size(); ++i) {
    if (seenBy[i] != 3) continue;
    const Vec3& v = solid.vertices[i];
    corners.push_back(frame_.to2D(p_ + (v - p_) * (pHeight_ / (pHeight_ - heights[i]))));
  }
  convexHullInto(corners, tolerance_.length(), outline);
  if (outline.size() < 3) return false;
  subtractShadow2D(outline, kNoGroup);
  return true;
}

bool Backprojection::occludeId(FaceId id) {
  if (isWholeObject(id)) return occludeObject(id.object);
  const Face* face = findFace(*scene_, id);
  return face && occlude(*face);
}

bool Backprojection::occludeFaces(std::span<const Face> faces) {
  bool any = false;
  for (const Face& face : faces) any = occlude(face) || any;
  return any;
}

const uint32_t* Backprojection::decidedGroup(uint32_t object) const {
  for (const auto& [known, group] : groups_)
    if (known == object) return &group;
  return nullptr;
}

uint32_t Backprojection::groupOf(uint32_t object) {
  if (const uint32_t* decided = decidedGroup(object)) return *decided;
  const uint32_t group = mergeableShadows(*scene_, object, lightPlane_, p_) ? object : kNoGroup;
  groups_.push_back({object, group});
  return group;
}

void Backprojection::subtractShadow(const Polygon3& onLightPlane, uint32_t group) {
  thread_local std::vector<Vec2> shadow;
  shadow.clear();
  for (const Vec3& q : onLightPlane) shadow.push_back(frame_.to2D(q));
  if (signedArea(shadow) < 0) std::reverse(shadow.begin(), shadow.end());
  subtractShadow2D(shadow, group);
}

void Backprojection::subtractShadow2D(std::span<const Vec2> shadow, uint32_t group) {
  ++comparisons_;
  if (!(std::abs(signedArea(shadow)) > tolerance_.area())) return;
  // Appended to the gathered shadows in the frame, counter-clockwise.
  shadowPoints_.insert(shadowPoints_.end(), shadow.begin(), shadow.end());
  shadowStarts_.push_back(uint32_t(shadowPoints_.size()));
  shadowGroups_.push_back(group);
  resolved_ = false;
}

bool Backprojection::mergedShadows(std::vector<Vec2>& points, std::vector<uint32_t>& starts) const {
  return mergeShadowGroups(shadowPoints_, shadowStarts_, shadowGroups_, tolerance_.length(), points, starts);
}

// Cut at a tenth of length(): a vertex within the cut tolerance of a shadow edge
// stays unmoved, and where several shadow edges nearly coincide (coplanar faces seen
// edge-on from a D⁰ point) a full length() snap shows as ~1e-9 relative error in the
// value.
double Backprojection::cutEps() const { return 0.1 * tolerance_.length(); }

void Backprojection::resolve() const {
  if (resolved_ || !applies_) return;
  resolved_ = true;
  // One contour per thread, its buffers reused from vertex to vertex; what is read
  // of it is kept here before another view on this thread computes again.
  thread_local VisibleContour contour;
  thread_local std::vector<Vec2> mergedPoints;
  thread_local std::vector<uint32_t> mergedStarts;
  if (mergedShadows(mergedPoints, mergedStarts))
    contour.compute(front2_, mergedPoints, mergedStarts, cutEps(), meshFacesAlone_);
  else
    contour.compute(front2_, shadowPoints_, shadowStarts_, cutEps(), meshFacesAlone_);
  if (chainObjects_.size() > 1) {
    thread_local std::vector<ChainEdge> merged;
    merged = chain_;
    mergeChainEdges(merged);
    contour.subtractChain(merged);
  } else {
    contour.subtractChain(chain_);
  }
  occluded_ = contour.occluded();
  anyVisible_ = contour.area() > tolerance_.area() && contour.anyLeft(tolerance_.length());
  visibleFactor_ = 0;
  if (!anyVisible_) return;
  if (!occluded_) {  // nothing removed: the front part itself, not its image in the frame
    visibleFactor_ = unoccludedFactor();
    return;
  }
  // Lambert's sum over the boundary of what is left, oriented as the light is in the frame
  // (counter-clockwise). The frame's normal is the light plane's (PlaneFrame: u × v = normal)
  // and p lies in front of that plane, so seen from p that boundary turns clockwise about the
  // direction the front part lies in (n's side): the sum is the integral negated. (Until
  // 2026-12 the light's own sum was computed at every point for this sign; it was negative at
  // every point of the bundled and generated scenes.)
  // With a shading normal the orientation still comes from n: the front part lies wholly in
  // front of n's plane, not of the shading normal's.
  double sum = 0;
  if (smooth_) {
    sum = shadedBoundarySum(contour.boundary());
  } else {
    for (const Segment2& s : contour.boundary())
      sum += lambertEdgeTerm(p_, n_, frame_.to3D(s.from), frame_.to3D(s.to));
  }
  visibleFactor_ = std::max(0.0, -0.5 * sum);
}

void Backprojection::resolvePieces(VisibleRegion& region) const {
  region.reset(front2_);
  std::vector<Vec2> points;
  std::vector<uint32_t> starts;
  if (!mergedShadows(points, starts)) points = shadowPoints_, starts = shadowStarts_;
  auto shadow = [&](size_t i) { return std::span<const Vec2>(points.data() + starts[i], points.data() + starts[i + 1]); };
  const size_t count = starts.size() - 1;
  // Largest overlap with the light's box first: in an umbra the light is gone
  // after few shadows, elsewhere later shadows find few pieces left to cut. Ties
  // keep the order given, so the result depends only on the set of shadows.
  Vec2 low = front2_[0], high = front2_[0];
  for (const Vec2& v : front2_) {
    low = glm::min(low, v);
    high = glm::max(high, v);
  }
  std::vector<std::pair<double, uint32_t>> order(count);
  for (size_t i = 0; i < count; ++i) {
    Vec2 sLow = shadow(i)[0], sHigh = shadow(i)[0];
    for (const Vec2& v : shadow(i)) {
      sLow = glm::min(sLow, v);
      sHigh = glm::max(sHigh, v);
    }
    const Vec2 overlap = glm::max(glm::min(high, sHigh) - glm::max(low, sLow), Vec2(0.0));
    order[i] = {-overlap.x * overlap.y, uint32_t(i)};
  }
  std::sort(order.begin(), order.end());
  for (const auto& [key, i] : order) {
    if (region.empty()) break;
    region.subtract(shadow(i), cutEps());
  }
}

double Backprojection::shadedBoundarySum(std::span<const Segment2> boundary) const {
  // The integrand is cos⁺ about s: the region is cut by the plane through p normal to s. Each
  // boundary segment keeps its part in front (d ≥ 0); where the boundary leaves the front at
  // x and comes back at y, the cut's boundary runs along the line where that plane meets the
  // light's, from x to y. Edge terms along one line are additive, so with F(q) the term from
  // the first crossing to q, the line's share is F(y) − F(x) summed over the pairs, which is
  // ΣF(entries) − ΣF(exits) whatever their pairing. (The term of a segment in that plane is
  // not zero: the cut is part of the boundary.)
  const Plane shade = Plane::throughPoint(s_, p_);
  double sum = 0, crossings = 0;
  bool anyCrossing = false;
  Vec3 origin{0.0};
  auto cross = [&](const Vec3& x, double sign) {
    if (!anyCrossing) origin = x, anyCrossing = true;
    crossings += sign * lambertEdgeTerm(p_, s_, origin, x);
  };
  for (const Segment2& segment : boundary) {
    const Vec3 a = frame_.to3D(segment.from), b = frame_.to3D(segment.to);
    const double da = shade.signedDistance(a), db = shade.signedDistance(b);
    const bool inA = da >= 0, inB = db >= 0;
    if (inA && inB) {
      sum += lambertEdgeTerm(p_, s_, a, b);
    } else if (inA != inB) {
      const Vec3 x = a + (b - a) * (da / (da - db));
      if (inA) {
        sum += lambertEdgeTerm(p_, s_, a, x);
        cross(x, -1);  // leaves the front
      } else {
        sum += lambertEdgeTerm(p_, s_, x, b);
        cross(x, +1);  // comes back
      }
    }
  }
  return sum + crossings;
}

double Backprojection::unoccludedFactor() const {
  if (!applies_) return 0.0;
  if (!smooth_) return lambertIntegral(p_, n_, front_);
  const Polygon3 shaded = clipFront(front_, Plane::throughPoint(s_, p_), tolerance_.length());
  return shaded.size() >= 3 ? lambertIntegral(p_, s_, shaded) : 0.0;
}

bool Backprojection::anyVisible() const {
  if (!applies_) return false;
  resolve();
  return anyVisible_;
}

double Backprojection::visibleFactor() const {
  if (!applies_) return 0;
  resolve();
  return visibleFactor_;
}

LightClass Backprojection::lightClass() const {
  if (!applies_) return LightClass::Lit;
  if (!anyVisible()) return LightClass::Umbra;
  return occluded_ ? LightClass::Penumbra : LightClass::Lit;
}

std::vector<Polygon3> Backprojection::visiblePieces() const {
  std::vector<Polygon3> out;
  if (!anyVisible()) return out;
  if (!occluded_) {
    out.push_back(front_);
    return out;
  }
  if (!chainObjects_.empty()) {  // convex pieces need the meshes' faces one by one
    Backprojection faceByFace = *this;
    faceByFace.chain_.clear();
    faceByFace.chainObjects_.clear();
    for (uint32_t handle : chainObjects_)
      for (const Face& face : scene_->facesOfObject(handle)) faceByFace.occlude(face);
    faceByFace.resolved_ = false;
    return faceByFace.visiblePieces();
  }
  VisibleRegion region;
  resolvePieces(region);
  for (size_t i = 0; i < region.pieceCount(); ++i) {
    if (!(signedArea(region.piece(i)) > tolerance_.area())) continue;
    Polygon3 world;
    for (const Vec2& q : region.piece(i)) world.push_back(frame_.to3D(q));
    out.push_back(std::move(world));
  }
  return out;
}

LightVisibleFactor backproject(const Scene& scene, size_t light, const Vec3& p, const Vec3& n,
                               std::span<const FaceId> candidates) {
  Backprojection view(scene, light, p, n);
  LightVisibleFactor out;
  out.applies = view.applies();
  if (!out.applies) return out;
  for (const FaceId id : candidates) view.occludeId(id);
  out.unoccludedFactor = view.unoccludedFactor();
  out.visibleFactor = view.visibleFactor();
  out.lightClass = view.lightClass();
  out.comparisons = view.comparisons();
  return out;
}

}  // namespace penumbra
