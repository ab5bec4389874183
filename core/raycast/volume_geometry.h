// A scene volume as an Embree user geometry (one primitive: the traced box under the object's
// transform), so isosurfaces share the polygons' BVH: the bounds, intersect and occluded
// callbacks map the ray to voxel space and call core/volume's octree trace. Built once with
// the RayScene, then read-only; the callbacks are thread-safe.
#pragma once

#include <embree3/rtcore.h>

#include "core/scene/volume_object.h"

namespace penumbra {

// Ray masks of the RayScene's geometries: polygon queries never see volumes, and the
// volume-only query (shadows of volumes on polygons) never sees polygons.
inline constexpr unsigned kPolygonRays = 1u;
inline constexpr unsigned kVolumeRays = 2u;
inline constexpr unsigned kAllRays = kPolygonRays | kVolumeRays;

struct VolumePlacement {
  const VolumeObject* volume = nullptr;
  Mat4 voxelFromWorld{1.0};
  Mat3 normalFromVoxel{1.0};          // inverse transpose of worldFromVoxel's linear part
  Vec3 worldMin{0.0}, worldMax{0.0};  // bounds of the traced box [0, size − 1]³ in world space
  double voxelSize = 1;  // cube root of a voxel's world volume (offsets for shadow rays)

  explicit VolumePlacement(const VolumeObject& object);
  // The world-space unit normal for a voxel-space gradient.
  Vec3 worldNormal(const Vec3& voxelGradient) const;
};

// Creates the user geometry (mask kVolumeRays), commits it and attaches it to `scene` as
// `geomID`. `placement` must outlive the scene.
void attachVolumeGeometry(RTCDevice device, RTCScene scene, const VolumePlacement& placement,
                          unsigned geomID);

}  // namespace penumbra
