#include "core/raycast/ray_scene.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

#include "core/util/parallel.h"

namespace penumbra {

namespace {

// Occlusion rays run from p (t = 0) to q (t = 1). The far end is generous on
// purpose: whether a hit lies between p and q is decided by the double-precision
// plane test in the filter, so Embree's float t only has to reach past 1 safely.
constexpr float kSegmentFar = 2.0f;

// The caller's data travels to the filter behind Embree's context (Embree 3's
// documented way to extend RTCIntersectContext: it must be the first member).
struct SegmentContext {
  RTCIntersectContext base;
  const Face* faces = nullptr;
  const RayScene::Geometry* geometries = nullptr;
  Vec3 p{0.0}, q{0.0};
  double onPlane = 0;
  std::vector<uint32_t>* blockers = nullptr;  // set: list every blocker, accept none
};

// SCENE_FORMAT.md's rule once Embree has found that the line crosses F's polygon:
// p strictly behind F (a plane containing p never blocks) and q strictly in front.
bool blocksSegment(const Plane& plane, const Vec3& p, const Vec3& q, double onPlane) {
  return plane.signedDistance(p) < -onPlane && plane.signedDistance(q) > onPlane;
}

void segmentFilter(const RTCFilterFunctionNArguments* args) {
  const auto* context = reinterpret_cast<const SegmentContext*>(args->context);
  for (unsigned i = 0; i < args->N; ++i) {
    if (args->valid[i] == 0) continue;
    const unsigned geomID = RTCHitN_geomID(args->hit, args->N, i);
    const unsigned primID = RTCHitN_primID(args->hit, args->N, i);
    const uint32_t faceIndex = context->geometries[geomID].faceOfTriangle[primID];
    const Plane& plane = context->faces[faceIndex].plane;
    if (!blocksSegment(plane, context->p, context->q, context->onPlane)) {
      args->valid[i] = 0;
    } else if (context->blockers) {
      context->blockers->push_back(faceIndex);
      args->valid[i] = 0;  // keep traversing to find the others
    }
  }
}

// What Embree's RayK::valid() asserts (kernels/common/ray.h): origin and direction components
// within FLT_LARGE (1.844e18) in magnitude, tnear and tfar not NaN; and a ray interval that is not
// empty. Checked on the float values Embree gets: a ray that fails is a miss, never handed over,
// so no input can reach Embree's assertion (issue 36).
constexpr float kEmbreeLargest = 1.8e18f;

bool finiteWithin(float x) { return std::isfinite(x) && std::fabs(x) <= kEmbreeLargest; }

bool embreeAccepts(const RTCRay& ray) {
  return finiteWithin(ray.org_x) && finiteWithin(ray.org_y) && finiteWithin(ray.org_z) &&
         finiteWithin(ray.dir_x) && finiteWithin(ray.dir_y) && finiteWithin(ray.dir_z) &&
         std::isfinite(ray.tnear) && ray.tnear >= 0 && !std::isnan(ray.tfar) &&
         ray.tfar >= ray.tnear;
}

void onEmbreeError(void* user, RTCError code, const char* message) {
  if (code == RTC_ERROR_NONE) return;
  static_cast<const RayScene*>(user)->recordError(message ? message : "unknown Embree error");
}

RTCRay segmentRay(const Vec3& p, const Vec3& q) {
  RTCRay ray{};
  ray.org_x = float(p.x);
  ray.org_y = float(p.y);
  ray.org_z = float(p.z);
  // The direction is formed in double so that q - p keeps its precision.
  const Vec3 d = q - p;
  ray.dir_x = float(d.x);
  ray.dir_y = float(d.y);
  ray.dir_z = float(d.z);
  ray.tnear = 0.0f;
  ray.tfar = kSegmentFar;
  ray.mask = kPolygonRays;
  ray.flags = 0;
  ray.time = 0.0f;
  return ray;
}

}  // namespace

void RayScene::recordError(const char* message) const {
  std::lock_guard lock(errorMutex_);
  if (lastError_.empty()) lastError_ = message;
}

void RayScene::check(const char* what) const {
  std::lock_guard lock(errorMutex_);
  if (!lastError_.empty()) throw RayTracingError(std::string(what) + ": " + lastError_);
}

RayScene::RayScene(const Scene& scene) : faces_(scene.faces()), tolerance_(scene.tolerance()) {
  // Embree builds its BVH on TBB, as uninstrumented as TBB itself: a TSan build builds it on the
  // calling thread, like the engine's loops (core/util/parallel.h).
  device_ = rtcNewDevice(kLoopsOnOneThread ? "threads=1" : nullptr);
  if (!device_) throw RayTracingError("Embree: cannot create a device");
  rtcSetDeviceErrorFunction(device_, onEmbreeError, this);
  // The blocking rule needs back-side hits and filter callbacks.
  if (rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_BACKFACE_CULLING_ENABLED) ||
      !rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED)) {
    rtcReleaseDevice(device_);
    throw RayTracingError("Embree: built with back-face culling or without filter functions");
  }

  scene_ = rtcNewScene(device_);
  rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_DYNAMIC | RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);

  // Scene::faces() is ordered by (object, face): each object's faces are contiguous.
  const auto& objects = scene.objects();
  geometries_.resize(objects.size());
  uint32_t faceIndex = 0;
  for (uint32_t o = 0; o < objects.size(); ++o) {
    Geometry& geometry = geometries_[o];
    geometry.firstFace = faceIndex;
    std::vector<float> vertices;
    std::vector<uint32_t> triangles;
    for (; faceIndex < faces_.size() && faces_[faceIndex].id.object == scene.handleOf(o); ++faceIndex) {
      const Polygon3& polygon = faces_[faceIndex].polygon;
      const uint32_t base = uint32_t(vertices.size() / 3);
      for (const Vec3& v : polygon) {
        vertices.push_back(float(v.x));
        vertices.push_back(float(v.y));
        vertices.push_back(float(v.z));
      }
      // Fan from vertex 0: faces are convex.
      for (uint32_t k = 1; k + 1 < polygon.size(); ++k) {
        triangles.insert(triangles.end(), {base, base + k, base + k + 1});
        geometry.faceOfTriangle.push_back(faceIndex);
        geometry.fanOfTriangle.push_back(k - 1);
      }
    }
    if (triangles.empty()) continue;

    RTCGeometry geom = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), vertices.size() / 3));
    auto* ib = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles.size() / 3));
    if (vb && ib) {
      std::copy(vertices.begin(), vertices.end(), vb);
      std::copy(triangles.begin(), triangles.end(), ib);
    }
    rtcSetGeometryOccludedFilterFunction(geom, segmentFilter);
    rtcSetGeometryMask(geom, kPolygonRays);
    rtcCommitGeometry(geom);
    // geomID == object index, so a later move can re-commit just that geometry.
    rtcAttachGeometryByID(scene_, geom, o);
    rtcReleaseGeometry(geom);
  }
  // Volumes after the polygons, in the same scene (and BVH); placements never move again.
  volumes_.reserve(scene.volumes().size());
  for (const VolumeObject& volume : scene.volumes()) volumes_.emplace_back(volume);
  for (size_t v = 0; v < volumes_.size(); ++v)
    attachVolumeGeometry(device_, scene_, volumes_[v], unsigned(objects.size() + v));
  rtcCommitScene(scene_);
  try {
    check("Embree scene build");
  } catch (...) {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
    throw;
  }
}

RayScene::~RayScene() {
  if (scene_) rtcReleaseScene(scene_);
  if (device_) rtcReleaseDevice(device_);
}

size_t RayScene::triangleCount() const {
  size_t count = 0;
  for (const Geometry& g : geometries_) count += g.faceOfTriangle.size();
  return count;
}

bool RayScene::traceSegment(const Vec3& p, const Vec3& q, std::vector<uint32_t>* blockers) const {
  SegmentContext context;
  rtcInitIntersectContext(&context.base);
  context.faces = faces_.data();
  context.geometries = geometries_.data();
  context.p = p;
  context.q = q;
  context.onPlane = tolerance_.onPlane();
  context.blockers = blockers;
  RTCRay ray = segmentRay(p, q);
  if (!embreeAccepts(ray)) return false;  // not a ray Embree can trace: nothing blocks it
  rtcOccluded1(scene_, &context.base, &ray);
  // Embree marks an occluded ray by setting tfar to -inf.
  return ray.tfar < 0.0f;
}

bool RayScene::occluded(const Vec3& p, const Vec3& q) const { return traceSegment(p, q, nullptr); }

std::vector<uint32_t> RayScene::blockers(const Vec3& p, const Vec3& q) const {
  std::vector<uint32_t> found;
  traceSegment(p, q, &found);
  std::sort(found.begin(), found.end());
  found.erase(std::unique(found.begin(), found.end()), found.end());
  return found;
}

bool RayScene::volumeOccluded(const Vec3& p, const Vec3& q) const {
  if (volumes_.empty()) return false;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRay ray = segmentRay(p, q);
  ray.tnear = 1e-6f;  // p itself may lie on the isosurface that was hit
  ray.tfar = 1.0f - 1e-6f;
  ray.mask = kVolumeRays;
  if (!embreeAccepts(ray)) return false;
  rtcOccluded1(scene_, &context, &ray);
  return ray.tfar < 0.0f;
}

std::optional<RayScene::Hit> RayScene::intersect(const Vec3& origin, const Vec3& dir, double tNear,
                                                 double tFar, unsigned mask) const {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  RTCRayHit rayHit{};
  rayHit.ray.org_x = float(origin.x);
  rayHit.ray.org_y = float(origin.y);
  rayHit.ray.org_z = float(origin.z);
  rayHit.ray.dir_x = float(dir.x);
  rayHit.ray.dir_y = float(dir.y);
  rayHit.ray.dir_z = float(dir.z);
  rayHit.ray.tnear = float(tNear);
  rayHit.ray.tfar = float(tFar);
  rayHit.ray.mask = mask;
  rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  if (!embreeAccepts(rayHit.ray)) return std::nullopt;  // a miss, never Embree's assertion
  rtcIntersect1(scene_, &context, &rayHit);
  if (rayHit.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
  if (rayHit.hit.geomID >= geometries_.size()) {
    Hit hit;
    hit.volume = uint32_t(rayHit.hit.geomID - geometries_.size());
    hit.t = rayHit.ray.tfar;
    hit.position = origin + hit.t * dir;
    hit.volumeNormal = glm::normalize(Vec3(rayHit.hit.Ng_x, rayHit.hit.Ng_y, rayHit.hit.Ng_z));
    hit.frontFacing = true;  // an isosurface is seen from either side
    return hit;
  }

  const Geometry& geometry = geometries_[rayHit.hit.geomID];
  Hit hit;
  hit.faceIndex = geometry.faceOfTriangle[rayHit.hit.primID];
  hit.fanTriangle = geometry.fanOfTriangle[rayHit.hit.primID];
  const Face& face = faces_[hit.faceIndex];
  hit.face = face.id;
  hit.barycentric = Vec2(rayHit.hit.u, rayHit.hit.v);
  hit.t = rayHit.ray.tfar;
  // Snap Embree's float hit point onto the face's double plane (a move along the
  // normal, so grazing rays cannot throw it far).
  hit.position = face.plane.project(origin + hit.t * dir);
  hit.frontFacing = glm::dot(face.plane.normal, dir) < 0;
  return hit;
}

std::optional<RayScene::Hit> RayScene::intersectFront(const Vec3& origin, const Vec3& dir, double tNear,
                                                      double tFar, unsigned mask) const {
  // Back faces are skipped by re-tracing just past them (relative to the ray parameter:
  // Embree's t is float); a ray crosses few of them.
  constexpr int kMaxBackFaceSkips = 64;
  constexpr double kSkipRelative = 1e-5;
  for (int pass = 0; pass < kMaxBackFaceSkips; ++pass) {
    auto hit = intersect(origin, dir, tNear, tFar, mask);
    if (!hit || hit->frontFacing) return hit;
    tNear = hit->t + kSkipRelative * std::max(hit->t, 1e-3);
  }
  return std::nullopt;
}

}  // namespace penumbra
