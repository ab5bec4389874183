// Embree 3 ray scene of a Scene's faces (one triangle geometry per object), with the
// single-sided blocking rule of SCENE_FORMAT.md, and its volume objects as user geometries in
// the same BVH (volume_geometry.h; seen only by queries that ask for them with a ray mask).
// Immutable after construction; queries are thread-safe.
#pragma once

#include <cmath>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/raycast/volume_geometry.h"
#include "core/scene/scene.h"

// Embree's handles, declared here so that users need not include rtcore.h.
struct RTCDeviceTy;
struct RTCSceneTy;

namespace penumbra {

// An Embree error (reported through the device's error callback).
class RayTracingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Precision: Embree traces in float. Whether a ray passes *inside* a face's polygon
// is Embree's float decision (about 1e-7 of the coordinates' size near edges and
// corners); everything about planes — which side p and q lie on, whether a face's
// plane contains p — is decided in double with the Scene's face planes and
// Tolerance::onPlane(). Points within ~1e-7 of the scene's size of a face's edge
// may be classified either way; that zone has measure zero for sampling.
// Every query first checks the float ray Embree would get (finite, components within 1.8e18, a
// non-empty interval): one that fails is a miss (nothing hit, nothing blocked), never traced.
class RayScene {
 public:
  struct Hit {
    FaceId face;
    uint32_t faceIndex = 0;  // index into Scene::faces()
    double t = 0;            // Embree's float distance along dir (dir not normalised)
    Vec3 position{0.0};      // origin + t·dir, snapped onto the face's plane
    Vec2 barycentric{0.0};   // Embree's (u, v) in the fan triangle (v0, v_k, v_k+1)
    uint32_t fanTriangle = 0;  // k - 1: which triangle of the face's fan
    bool frontFacing = false;  // dir points against the face's front normal
    // A volume's isosurface (kVolumeRays queries only): its index in Scene::volumes() and the
    // world unit normal (towards larger values); face / faceIndex / barycentric are then unset.
    std::optional<uint32_t> volume;
    Vec3 volumeNormal{0.0};
  };

  // Builds one triangle geometry per object (faces fan-triangulated) and commits.
  // Throws RayTracingError if Embree reports an error.
  explicit RayScene(const Scene& scene);
  ~RayScene();
  RayScene(const RayScene&) = delete;
  RayScene& operator=(const RayScene&) = delete;

  // SCENE_FORMAT.md: the segment p→q is blocked by a face F iff it crosses F and q
  // lies strictly in front of F's plane (beyond onPlane()); a face whose plane
  // contains p (|dist| ≤ onPlane()) never blocks p. Lights are not in the scene.
  bool occluded(const Vec3& p, const Vec3& q) const;
  // Every face that blocks p→q by the same rule (indices into Scene::faces(),
  // sorted, unique). For tests and diagnostics; slower than occluded().
  std::vector<uint32_t> blockers(const Vec3& p, const Vec3& q) const;
  // Whether a volume's isosurface crosses the segment p→q (t in (0, 1) of q − p); polygons
  // are not looked at. False when the scene has no volumes.
  bool volumeOccluded(const Vec3& p, const Vec3& q) const;
  bool hasVolumes() const { return !volumes_.empty(); }
  const VolumePlacement& volumePlacement(uint32_t volume) const { return volumes_[volume]; }

  // Closest face hit by origin + t·dir, t in [tNear, tFar], from either side; with
  // mask kAllRays volume isosurfaces too (their hits count as front-facing).
  std::optional<Hit> intersect(const Vec3& origin, const Vec3& dir, double tNear = 0,
                               double tFar = INFINITY, unsigned mask = kPolygonRays) const;
  // Closest front-facing hit: faces seen from behind are passed through (faces are
  // single-sided: a face blocks only what lies in front of it), at most 64 of them.
  std::optional<Hit> intersectFront(const Vec3& origin, const Vec3& dir, double tNear = 0,
                                    double tFar = INFINITY, unsigned mask = kPolygonRays) const;

  const Face& face(uint32_t faceIndex) const { return faces_[faceIndex]; }
  size_t triangleCount() const;

  // Used by the Embree filter callbacks (ray_scene.cpp); not part of the API.
  struct Geometry {
    uint32_t firstFace = 0;                // index into faces_ of the object's face 0
    std::vector<uint32_t> faceOfTriangle;  // primID -> index into faces_
    std::vector<uint32_t> fanOfTriangle;   // primID -> k - 1
  };
  // Called by Embree's error callback; the next check() throws with the message.
  void recordError(const char* message) const;

 private:
  void check(const char* what) const;
  // Whether some face blocks p→q; with `blockers`, lists every one instead of stopping.
  bool traceSegment(const Vec3& p, const Vec3& q, std::vector<uint32_t>* blockers) const;

  std::vector<Face> faces_;  // copy of Scene::faces(): planes in double for the filters
  std::vector<Geometry> geometries_;  // one per object; geomID == object index
  // One per volume object, geomID == objects + volume index; the callbacks point into it.
  std::vector<VolumePlacement> volumes_;
  Tolerance tolerance_;
  RTCDeviceTy* device_ = nullptr;
  RTCSceneTy* scene_ = nullptr;
  // Written by Embree's error callback (any thread), read by check().
  mutable std::mutex errorMutex_;
  mutable std::string lastError_;
};

}  // namespace penumbra
