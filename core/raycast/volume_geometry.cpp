#include "core/raycast/volume_geometry.h"

#include <cmath>
#include <limits>

namespace penumbra {

namespace {

Vec3 transformPoint(const Mat4& m, const Vec3& p) { return Vec3(m * glm::dvec4(p, 1.0)); }

void volumeBounds(const RTCBoundsFunctionArguments* args) {
  const auto* placement = static_cast<const VolumePlacement*>(args->geometryUserPtr);
  // Float bounds rounded outwards by a relative margin: Embree must never cull a ray that
  // the double-precision trace would hit.
  const Vec3 pad = 1e-5 * (placement->worldMax - placement->worldMin) + Vec3(1e-6);
  const Vec3 lo = placement->worldMin - pad, hi = placement->worldMax + pad;
  args->bounds_o->lower_x = float(lo.x);
  args->bounds_o->lower_y = float(lo.y);
  args->bounds_o->lower_z = float(lo.z);
  args->bounds_o->upper_x = float(hi.x);
  args->bounds_o->upper_y = float(hi.y);
  args->bounds_o->upper_z = float(hi.z);
}

// The ray in voxel space: an affine map keeps the ray parameter t.
std::optional<volume::VolumeHit> traceRay(const VolumePlacement& placement, RTCRayN* rays,
                                          unsigned n, unsigned i) {
  const Vec3 origin(RTCRayN_org_x(rays, n, i), RTCRayN_org_y(rays, n, i),
                    RTCRayN_org_z(rays, n, i));
  const Vec3 dir(RTCRayN_dir_x(rays, n, i), RTCRayN_dir_y(rays, n, i), RTCRayN_dir_z(rays, n, i));
  volume::VolumeRay ray;
  ray.origin = transformPoint(placement.voxelFromWorld, origin);
  ray.dir = Mat3(placement.voxelFromWorld) * dir;
  ray.tMin = RTCRayN_tnear(rays, n, i);
  ray.tMax = RTCRayN_tfar(rays, n, i);
  if (!(ray.tMax >= ray.tMin)) return std::nullopt;
  return placement.volume->data->trace(ray, placement.volume->isovalue);
}

void volumeIntersect(const RTCIntersectFunctionNArguments* args) {
  const auto* placement = static_cast<const VolumePlacement*>(args->geometryUserPtr);
  RTCRayN* rays = RTCRayHitN_RayN(args->rayhit, args->N);
  RTCHitN* hits = RTCRayHitN_HitN(args->rayhit, args->N);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const auto hit = traceRay(*placement, rays, args->N, i);
    if (!hit || !(float(hit->t) <= RTCRayN_tfar(rays, args->N, i))) continue;
    RTCRayN_tfar(rays, args->N, i) = float(hit->t);
    const Vec3 normal = placement->worldNormal(hit->normal);
    RTCHitN_Ng_x(hits, args->N, i) = float(normal.x);
    RTCHitN_Ng_y(hits, args->N, i) = float(normal.y);
    RTCHitN_Ng_z(hits, args->N, i) = float(normal.z);
    RTCHitN_u(hits, args->N, i) = 0.0f;
    RTCHitN_v(hits, args->N, i) = 0.0f;
    RTCHitN_primID(hits, args->N, i) = args->primID;
    RTCHitN_geomID(hits, args->N, i) = args->geomID;
    RTCHitN_instID(hits, args->N, i, 0) = args->context->instID[0];
  }
}

void volumeOccluded(const RTCOccludedFunctionNArguments* args) {
  const auto* placement = static_cast<const VolumePlacement*>(args->geometryUserPtr);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    if (traceRay(*placement, args->ray, args->N, i))
      RTCRayN_tfar(args->ray, args->N, i) = -std::numeric_limits<float>::infinity();
  }
}

}  // namespace

VolumePlacement::VolumePlacement(const VolumeObject& object) : volume(&object) {
  const Mat4 worldFromVoxel = object.worldFromVoxel();
  voxelFromWorld = glm::inverse(worldFromVoxel);
  normalFromVoxel = glm::transpose(Mat3(voxelFromWorld));
  voxelSize = std::cbrt(std::abs(glm::determinant(Mat3(worldFromVoxel))));
  const Vec3 top = Vec3(object.data->size() - glm::ivec3(1));
  worldMin = Vec3(std::numeric_limits<double>::infinity());
  worldMax = -worldMin;
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 voxel((corner & 4) ? top.x : 0.0, (corner & 2) ? top.y : 0.0,
                     (corner & 1) ? top.z : 0.0);
    const Vec3 world = transformPoint(worldFromVoxel, voxel);
    worldMin = glm::min(worldMin, world);
    worldMax = glm::max(worldMax, world);
  }
}

Vec3 VolumePlacement::worldNormal(const Vec3& voxelGradient) const {
  const Vec3 n = normalFromVoxel * voxelGradient;
  const double length = glm::length(n);
  return length > 0 ? n / length : Vec3(0, 1, 0);
}

void attachVolumeGeometry(RTCDevice device, RTCScene scene, const VolumePlacement& placement,
                          unsigned geomID) {
  RTCGeometry geom = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
  rtcSetGeometryUserPrimitiveCount(geom, 1);
  rtcSetGeometryUserData(geom, const_cast<VolumePlacement*>(&placement));  // read-only in callbacks
  rtcSetGeometryBoundsFunction(geom, volumeBounds, nullptr);
  rtcSetGeometryIntersectFunction(geom, volumeIntersect);
  rtcSetGeometryOccludedFunction(geom, volumeOccluded);
  rtcSetGeometryMask(geom, kVolumeRays);
  rtcCommitGeometry(geom);
  rtcAttachGeometryByID(scene, geom, geomID);
  rtcReleaseGeometry(geom);
}

}  // namespace penumbra
