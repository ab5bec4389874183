// Camera maths: the view matrix (three.js lookAt), projection matrices as "Deriving Projection
// Matrices" derives them (perspective, off-centre frustum, orthographic) for either depth range
// and view-space handedness, and world ↔ NDC ↔ pixel mappings. Plain values; thread-safe.
#pragma once

#include <optional>

#include "core/geom/vec.h"
#include "core/scene/scene.h"

namespace penumbra {

// The canonical view volume's depth: [-1, 1] (OpenGL, WebGL, three.js) or [0, 1]
// (Direct3D, Vulkan, WebGPU; the derivation's own choice).
enum class DepthRange { MinusOneToOne, ZeroToOne };
// View space: right-handed looks down -z (OpenGL, three.js); left-handed looks down +z
// (Direct3D; the derivation's own choice).
enum class Handedness { Right, Left };

struct ClipConvention {
  DepthRange depth = DepthRange::MinusOneToOne;
  Handedness hand = Handedness::Right;
};

// The view volume's sides in view space, as the derivation names them: the near plane spans
// [left, right] × [bottom, top]; near and far are positive distances along the view direction.
struct Frustum {
  double left = -1, right = 1, bottom = -1, top = 1, near = 0.1, far = 100;
};

// The symmetric frustum of a vertical field of view (radians) — three.js PerspectiveCamera:
// top = near·tan(fov/2), right = aspect·top.
Frustum perspectiveFrustum(double fovYRadians, double aspect, double near, double far);
// The symmetric box of an orthographic view `height` tall: top = height/2, right = aspect·top.
Frustum orthographicFrustum(double height, double aspect, double near, double far);

// Perspective projection of a (possibly off-centre) frustum: the derivation's P_p, with the
// depth row solved for the convention's depth range and the sign of z set by the handedness.
Mat4 perspectiveMatrix(const Frustum& frustum, ClipConvention convention = {});
// The same for a vertical field of view (radians) and aspect = width / height.
Mat4 perspectiveMatrix(double fovYRadians, double aspect, double near, double far,
                       ClipConvention convention = {});
// Orthographic projection of a (possibly off-centre) box: the derivation's P_o.
Mat4 orthographicMatrix(const Frustum& box, ClipConvention convention = {});

// World → view space, as three.js Object3D.lookAt / Matrix4.lookAt builds it: camera z axis =
// normalize(eye − target), x = normalize(up × z), y = z × x. A left-handed view space is the
// same camera with z negated, so both conventions draw the same (unmirrored) image.
// `up` must not be parallel to the view direction.
Mat4 viewMatrix(const Vec3& eye, const Vec3& target, const Vec3& up, Handedness hand = Handedness::Right);

// NDC (x, y in [-1, 1], y up) → continuous pixel coordinates of a width × height image with
// y down: pixel (i, j) covers [i, i+1) × [j, j+1) and its centre is (i + 0.5, j + 0.5).
Vec2 ndcToPixel(const Vec2& ndc, int width, int height);
Vec2 pixelToNdc(const Vec2& pixel, int width, int height);

// A Camera seen through a width × height image: the exact matrices the renderer uses.
class CameraProjection {
 public:
  // Throws std::invalid_argument on a non-positive size or a degenerate camera.
  CameraProjection(const Camera& camera, int width, int height, ClipConvention convention = {});

  const Mat4& view() const { return view_; }
  const Mat4& projection() const { return projection_; }
  const Mat4& viewProjection() const { return viewProjection_; }
  const Frustum& frustum() const { return frustum_; }
  ClipConvention convention() const { return convention_; }
  int width() const { return width_; }
  int height() const { return height_; }

  // World → NDC (after the perspective divide); nullopt behind the eye (w ≤ 0).
  std::optional<Vec3> toNdc(const Vec3& world) const;
  // World → continuous pixel coordinates (y down); nullopt behind the eye.
  std::optional<Vec2> toPixel(const Vec3& world) const;
  // The integer pixel containing a world point; nullopt outside the image or the depth range.
  struct PixelIndex {
    int i = 0, j = 0;  // column, row (row 0 at the top)
  };
  std::optional<PixelIndex> pixelOf(const Vec3& world) const;

  // The primary ray through continuous pixel coordinates: from the point on the near plane to
  // the point on the far plane, both unprojected with the inverse view-projection (so every
  // point on the ray projects back to that pixel). dir = far point − near point.
  struct Ray {
    Vec3 origin{0.0};
    Vec3 dir{0.0};
  };
  Ray rayThrough(const Vec2& pixel) const;

 private:
  Vec3 unproject(const Vec3& ndc) const;

  ClipConvention convention_;
  int width_ = 0, height_ = 0;
  Frustum frustum_;
  Mat4 view_{1.0}, projection_{1.0}, viewProjection_{1.0}, inverseViewProjection_{1.0};
};

// A camera that frames the scene's bounds: from the bounds' centre, backed off along
// (0.6, 0.45, 1) until the bounding sphere fits a 45° vertical field of view.
Camera defaultCamera(const Bounds& bounds);

}  // namespace penumbra
