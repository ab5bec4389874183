#include "core/raycast/camera_projection.h"

#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {

// GLM is column-major (m[column][row]); the derivation writes rows. This sets row r, column c.
void set(Mat4& m, int row, int column, double value) { m[column][row] = value; }

// +1 when the view direction is +z (left-handed), −1 when it is −z (right-handed).
double viewSign(Handedness hand) { return hand == Handedness::Left ? 1.0 : -1.0; }

void checkFrustum(const Frustum& f) {
  if (!(f.right != f.left && f.top != f.bottom && f.far != f.near))
    throw std::invalid_argument("projection: empty view volume");
}

}  // namespace

Frustum perspectiveFrustum(double fovYRadians, double aspect, double near, double far) {
  const double top = near * std::tan(fovYRadians / 2);
  const double right = aspect * top;
  return Frustum{-right, right, -top, top, near, far};
}

Frustum orthographicFrustum(double height, double aspect, double near, double far) {
  const double top = height / 2;
  const double right = aspect * top;
  return Frustum{-right, right, -top, top, near, far};
}

Mat4 perspectiveMatrix(const Frustum& f, ClipConvention convention) {
  checkFrustum(f);
  // With d = s·z the distance along the view direction, the derivation gives
  //   x'd = 2n/(r−l)·x − (r+l)/(r−l)·d,   y'd = 2n/(t−b)·y − (t+b)/(t−b)·d,   w' = d,
  // and z'd = p·d + q with z' = low at d = n and z' = 1 at d = f.
  const double s = viewSign(convention.hand);
  const double n = f.near, fa = f.far, l = f.left, r = f.right, b = f.bottom, t = f.top;
  double p = 0, q = 0;
  if (convention.depth == DepthRange::ZeroToOne) {
    p = fa / (fa - n);  // 0 = p·n + q, f = p·f + q
    q = -fa * n / (fa - n);
  } else {
    p = (fa + n) / (fa - n);  // −n = p·n + q, f = p·f + q
    q = -2 * fa * n / (fa - n);
  }
  Mat4 m(0.0);
  set(m, 0, 0, 2 * n / (r - l));
  set(m, 0, 2, -s * (r + l) / (r - l));
  set(m, 1, 1, 2 * n / (t - b));
  set(m, 1, 2, -s * (t + b) / (t - b));
  set(m, 2, 2, s * p);
  set(m, 2, 3, q);
  set(m, 3, 2, s);
  return m;
}

Mat4 perspectiveMatrix(double fovYRadians, double aspect, double near, double far,
                       ClipConvention convention) {
  return perspectiveMatrix(perspectiveFrustum(fovYRadians, aspect, near, far), convention);
}

Mat4 orthographicMatrix(const Frustum& f, ClipConvention convention) {
  checkFrustum(f);
  // x' = 2x/(r−l) − (r+l)/(r−l), y' likewise; z' = p·d + q with d = s·z as above.
  const double s = viewSign(convention.hand);
  const double n = f.near, fa = f.far, l = f.left, r = f.right, b = f.bottom, t = f.top;
  double p = 0, q = 0;
  if (convention.depth == DepthRange::ZeroToOne) {
    p = 1 / (fa - n);
    q = -n / (fa - n);
  } else {
    p = 2 / (fa - n);
    q = -(fa + n) / (fa - n);
  }
  Mat4 m(1.0);
  set(m, 0, 0, 2 / (r - l));
  set(m, 0, 3, -(r + l) / (r - l));
  set(m, 1, 1, 2 / (t - b));
  set(m, 1, 3, -(t + b) / (t - b));
  set(m, 2, 2, s * p);
  set(m, 2, 3, q);
  return m;
}

Mat4 viewMatrix(const Vec3& eye, const Vec3& target, const Vec3& up, Handedness hand) {
  const Vec3 back = eye - target;
  if (!(glm::length(back) > 0)) throw std::invalid_argument("view: target is at the eye");
  const Vec3 z = glm::normalize(back);
  const Vec3 side = glm::cross(up, z);
  if (!(glm::length(side) > 1e-12 * glm::length(up)))
    throw std::invalid_argument("view: up is parallel to the view direction");
  const Vec3 x = glm::normalize(side);
  const Vec3 y = glm::cross(z, x);
  const Vec3 zRow = hand == Handedness::Left ? -z : z;
  Mat4 m(1.0);
  const Vec3 rows[3] = {x, y, zRow};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) set(m, r, c, rows[r][c]);
    set(m, r, 3, -glm::dot(rows[r], eye));
  }
  return m;
}

Vec2 ndcToPixel(const Vec2& ndc, int width, int height) {
  return Vec2{(ndc.x + 1) / 2 * width, (1 - ndc.y) / 2 * height};
}

Vec2 pixelToNdc(const Vec2& pixel, int width, int height) {
  return Vec2{2 * pixel.x / width - 1, 1 - 2 * pixel.y / height};
}

CameraProjection::CameraProjection(const Camera& camera, int width, int height,
                                   ClipConvention convention)
    : convention_(convention), width_(width), height_(height) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("camera: image size must be positive");
  if (!(camera.near > 0 && camera.far > camera.near))
    throw std::invalid_argument("camera: need 0 < near < far");
  const double aspect = double(width) / double(height);
  if (camera.projection == Camera::Projection::Perspective) {
    if (!(camera.fovYDeg > 0 && camera.fovYDeg < 180))
      throw std::invalid_argument("camera: fov_y_deg must be in (0, 180)");
    frustum_ = perspectiveFrustum(glm::radians(camera.fovYDeg), aspect, camera.near, camera.far);
    projection_ = perspectiveMatrix(frustum_, convention);
  } else {
    if (!(camera.height > 0)) throw std::invalid_argument("camera: height must be positive");
    frustum_ = orthographicFrustum(camera.height, aspect, camera.near, camera.far);
    projection_ = orthographicMatrix(frustum_, convention);
  }
  view_ = viewMatrix(camera.position, camera.target, camera.up, convention.hand);
  viewProjection_ = projection_ * view_;
  inverseViewProjection_ = glm::inverse(viewProjection_);
}

std::optional<Vec3> CameraProjection::toNdc(const Vec3& world) const {
  const glm::dvec4 clip = viewProjection_ * glm::dvec4(world, 1.0);
  if (!(clip.w > 0)) return std::nullopt;
  return Vec3(clip) / clip.w;
}

std::optional<Vec2> CameraProjection::toPixel(const Vec3& world) const {
  const auto ndc = toNdc(world);
  if (!ndc) return std::nullopt;
  return ndcToPixel(Vec2(*ndc), width_, height_);
}

std::optional<CameraProjection::PixelIndex> CameraProjection::pixelOf(const Vec3& world) const {
  const auto ndc = toNdc(world);
  if (!ndc) return std::nullopt;
  const double low = convention_.depth == DepthRange::ZeroToOne ? 0.0 : -1.0;
  if (!(ndc->z >= low && ndc->z <= 1)) return std::nullopt;
  const Vec2 pixel = ndcToPixel(Vec2(*ndc), width_, height_);
  const int i = int(std::floor(pixel.x)), j = int(std::floor(pixel.y));
  if (i < 0 || i >= width_ || j < 0 || j >= height_) return std::nullopt;
  return PixelIndex{i, j};
}

Vec3 CameraProjection::unproject(const Vec3& ndc) const {
  const glm::dvec4 world = inverseViewProjection_ * glm::dvec4(ndc, 1.0);
  return Vec3(world) / world.w;
}

CameraProjection::Ray CameraProjection::rayThrough(const Vec2& pixel) const {
  const Vec2 ndc = pixelToNdc(pixel, width_, height_);
  const double nearDepth = convention_.depth == DepthRange::ZeroToOne ? 0.0 : -1.0;
  const Vec3 nearPoint = unproject(Vec3(ndc, nearDepth));
  const Vec3 farPoint = unproject(Vec3(ndc, 1.0));
  return Ray{nearPoint, farPoint - nearPoint};
}

Camera defaultCamera(const Bounds& bounds) {
  Camera camera;
  const double radius = std::max(bounds.diagonal() / 2, 1e-6);
  const double fov = 45;
  const double distance = radius / std::sin(glm::radians(fov) / 2);
  camera.target = bounds.center();
  camera.position = camera.target + distance * glm::normalize(Vec3(0.6, 0.45, 1.0));
  camera.up = Vec3(0, 1, 0);
  camera.projection = Camera::Projection::Perspective;
  camera.fovYDeg = fov;
  camera.near = std::max(distance - 1.01 * radius, 1e-3 * distance);
  camera.far = distance + 1.01 * radius;
  return camera;
}

}  // namespace penumbra
