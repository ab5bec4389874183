// Camera projection against independent derivations: the matrices of "Deriving Projection
// Matrices" written out element by element, GLM's clip-space functions, three.js's camera
// formulas (PerspectiveCamera / OrthographicCamera / Matrix4.lookAt) written out here, frustum
// corners landing on the canonical volume's corners, and pixel ↔ ray round trips.
#include "core/raycast/camera_projection.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <glm/ext/matrix_clip_space.hpp>
#include <glm/ext/matrix_transform.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <random>

namespace penumbra {
namespace {

constexpr double kExact = 1e-12;

// A matrix from its rows as the derivation prints them.
Mat4 fromRows(const std::array<std::array<double, 4>, 4>& rows) {
  Mat4 m(0.0);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[c][r] = rows[r][c];
  return m;
}

void expectMatrixNear(const Mat4& actual, const Mat4& expected, double tolerance, const std::string& what) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      EXPECT_NEAR(actual[c][r], expected[c][r], tolerance) << what << ": row " << r << " column " << c;
}

const std::array<ClipConvention, 4> kConventions = {
    ClipConvention{DepthRange::MinusOneToOne, Handedness::Right},
    ClipConvention{DepthRange::ZeroToOne, Handedness::Right},
    ClipConvention{DepthRange::MinusOneToOne, Handedness::Left},
    ClipConvention{DepthRange::ZeroToOne, Handedness::Left}};

std::string name(ClipConvention c) {
  return std::string(c.hand == Handedness::Right ? "RH" : "LH") +
         (c.depth == DepthRange::ZeroToOne ? "_ZO" : "_NO");
}

const Frustum kOffCentre{-0.3, 0.5, -0.2, 0.45, 0.5, 20.0};

// --- The derivation (left-handed, depth 0..1) ------------------------------------------------

TEST(CameraProjection, PerspectiveOffCentreIsTheDerivationsPp) {
  const double l = kOffCentre.left, r = kOffCentre.right, b = kOffCentre.bottom, t = kOffCentre.top;
  const double n = kOffCentre.near, f = kOffCentre.far;
  const Mat4 paper = fromRows({{{2 * n / (r - l), 0, -(r + l) / (r - l), 0},
                                {0, 2 * n / (t - b), -(t + b) / (t - b), 0},
                                {0, 0, f / (f - n), -f * n / (f - n)},
                                {0, 0, 1, 0}}});
  expectMatrixNear(perspectiveMatrix(kOffCentre, {DepthRange::ZeroToOne, Handedness::Left}), paper, kExact,
                   "P_p off-centre");
}

TEST(CameraProjection, PerspectiveSymmetricIsTheDerivationsWidthHeightForm) {
  const double w = 0.8, h = 0.6, n = 0.25, f = 50;
  const Mat4 paper = fromRows({{{2 * n / w, 0, 0, 0}, {0, 2 * n / h, 0, 0}, {0, 0, f / (f - n), -f * n / (f - n)}, {0, 0, 1, 0}}});
  expectMatrixNear(perspectiveMatrix(Frustum{-w / 2, w / 2, -h / 2, h / 2, n, f},
                                     {DepthRange::ZeroToOne, Handedness::Left}),
                   paper, kExact, "P_p (w, h)");
}

TEST(CameraProjection, PerspectiveFovIsTheDerivationsCotangentForm) {
  const double a = glm::radians(50.0), aspect = 16.0 / 9.0, n = 0.1, f = 100;
  const double cot = 1 / std::tan(a / 2);
  const Mat4 paper = fromRows({{{cot / aspect, 0, 0, 0}, {0, cot, 0, 0}, {0, 0, f / (f - n), -f * n / (f - n)}, {0, 0, 1, 0}}});
  expectMatrixNear(perspectiveMatrix(a, aspect, n, f, {DepthRange::ZeroToOne, Handedness::Left}), paper, kExact,
                   "P_p (fov, aspect)");
}

TEST(CameraProjection, OrthographicIsTheDerivationsPoAndItsScaleTranslateFactoring) {
  const double l = kOffCentre.left, r = kOffCentre.right, b = kOffCentre.bottom, t = kOffCentre.top;
  const double n = kOffCentre.near, f = kOffCentre.far;
  const Mat4 paper = fromRows({{{2 / (r - l), 0, 0, -(r + l) / (r - l)},
                                {0, 2 / (t - b), 0, -(t + b) / (t - b)},
                                {0, 0, 1 / (f - n), -n / (f - n)},
                                {0, 0, 0, 1}}});
  const ClipConvention d3d{DepthRange::ZeroToOne, Handedness::Left};
  expectMatrixNear(orthographicMatrix(kOffCentre, d3d), paper, kExact, "P_o off-centre");

  // Centred: P_o = S·T, a translation of the near plane to the origin, then a scale.
  const double w = 3, h = 2;
  const Mat4 scale = fromRows({{{2 / w, 0, 0, 0}, {0, 2 / h, 0, 0}, {0, 0, 1 / (f - n), 0}, {0, 0, 0, 1}}});
  const Mat4 translate = fromRows({{{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, -n}, {0, 0, 0, 1}}});
  expectMatrixNear(orthographicMatrix(orthographicFrustum(h, w / h, n, f), d3d), scale * translate, kExact,
                   "P_o = S T");
}

// --- GLM 0.9.9.8 ----------------------------------------------------------------------------

Mat4 glmPerspective(ClipConvention c, double fov, double aspect, double n, double f) {
  if (c.hand == Handedness::Right)
    return c.depth == DepthRange::ZeroToOne ? glm::perspectiveRH_ZO(fov, aspect, n, f)
                                            : glm::perspectiveRH_NO(fov, aspect, n, f);
  return c.depth == DepthRange::ZeroToOne ? glm::perspectiveLH_ZO(fov, aspect, n, f)
                                          : glm::perspectiveLH_NO(fov, aspect, n, f);
}

Mat4 glmFrustum(ClipConvention c, const Frustum& v) {
  if (c.hand == Handedness::Right)
    return c.depth == DepthRange::ZeroToOne ? glm::frustumRH_ZO(v.left, v.right, v.bottom, v.top, v.near, v.far)
                                            : glm::frustumRH_NO(v.left, v.right, v.bottom, v.top, v.near, v.far);
  return c.depth == DepthRange::ZeroToOne ? glm::frustumLH_ZO(v.left, v.right, v.bottom, v.top, v.near, v.far)
                                          : glm::frustumLH_NO(v.left, v.right, v.bottom, v.top, v.near, v.far);
}

Mat4 glmOrtho(ClipConvention c, const Frustum& v) {
  if (c.hand == Handedness::Right)
    return c.depth == DepthRange::ZeroToOne ? glm::orthoRH_ZO(v.left, v.right, v.bottom, v.top, v.near, v.far)
                                            : glm::orthoRH_NO(v.left, v.right, v.bottom, v.top, v.near, v.far);
  return c.depth == DepthRange::ZeroToOne ? glm::orthoLH_ZO(v.left, v.right, v.bottom, v.top, v.near, v.far)
                                          : glm::orthoLH_NO(v.left, v.right, v.bottom, v.top, v.near, v.far);
}

TEST(CameraProjection, AgreesWithGlmPerspectiveAndOrthoInEveryConvention) {
  for (ClipConvention c : kConventions) {
    expectMatrixNear(perspectiveMatrix(glm::radians(45.0), 1.5, 0.1, 100, c),
                     glmPerspective(c, glm::radians(45.0), 1.5, 0.1, 100), kExact, "perspective " + name(c));
    expectMatrixNear(orthographicMatrix(kOffCentre, c), glmOrtho(c, kOffCentre), kExact, "ortho " + name(c));
    // Symmetric frusta: glm::frustum* in every convention.
    const Frustum symmetric = perspectiveFrustum(glm::radians(60.0), 0.75, 0.2, 30);
    expectMatrixNear(perspectiveMatrix(symmetric, c), glmFrustum(c, symmetric), kExact, "frustum " + name(c));
  }
  // Off-centre right-handed frusta: glm::frustumRH_*.
  for (ClipConvention c : {kConventions[0], kConventions[1]})
    expectMatrixNear(perspectiveMatrix(kOffCentre, c), glmFrustum(c, kOffCentre), kExact, "off-centre " + name(c));
}

// GLM 0.9.9.8's frustumLH_ZO/_NO put +(r+l)/(r−l) and +(t+b)/(t−b) in the third column, where a
// left-handed frustum (w = +z) needs the derivation's −(r+l)/(r−l): its near-plane corners then
// miss the canonical volume's corners. Ours equals GLM's with those two signs flipped.
TEST(CameraProjection, GlmLeftHandedOffCentreFrustumHasTheOffCentreSignFlipped) {
  for (ClipConvention c : {kConventions[2], kConventions[3]}) {
    Mat4 corrected = glmFrustum(c, kOffCentre);
    corrected[2][0] = -corrected[2][0];
    corrected[2][1] = -corrected[2][1];
    expectMatrixNear(perspectiveMatrix(kOffCentre, c), corrected, kExact, "LH off-centre " + name(c));
    const glm::dvec4 corner = glmFrustum(c, kOffCentre) * glm::dvec4(kOffCentre.right, kOffCentre.top, kOffCentre.near, 1);
    EXPECT_GT(std::abs(corner.x / corner.w - 1), 0.1) << "GLM now maps the corner right: drop this workaround note";
  }
}

TEST(CameraProjection, ViewMatrixIsGlmLookAtRightHandedAndItsZFlipLeftHanded) {
  const Vec3 eye(2.78, 2.73, -8), target(2.5, 2.0, 0.3), up(0.1, 1, 0);
  expectMatrixNear(viewMatrix(eye, target, up, Handedness::Right), glm::lookAtRH(eye, target, up), kExact, "lookAtRH");
  const Mat4 flipZ = glm::scale(Mat4(1.0), Vec3(1, 1, -1));
  expectMatrixNear(viewMatrix(eye, target, up, Handedness::Left), flipZ * glm::lookAtRH(eye, target, up), kExact,
                   "LH view");
  EXPECT_THROW(viewMatrix(eye, eye, up), std::invalid_argument);
  EXPECT_THROW(viewMatrix(eye, eye + Vec3(0, 2, 0), Vec3(0, 1, 0)), std::invalid_argument);  // up ∥ view
}

// --- The canonical view volume ---------------------------------------------------------------

TEST(CameraProjection, FrustumCornersMapToCanonicalCorners) {
  for (ClipConvention c : kConventions) {
    const double s = c.hand == Handedness::Left ? 1 : -1;  // view direction along s·z
    const double low = c.depth == DepthRange::ZeroToOne ? 0 : -1;
    for (bool perspective : {true, false}) {
      const Mat4 m = perspective ? perspectiveMatrix(kOffCentre, c) : orthographicMatrix(kOffCentre, c);
      for (int corner = 0; corner < 8; ++corner) {
        const bool right = corner & 1, top = corner & 2, far = corner & 4;
        const double d = far ? kOffCentre.far : kOffCentre.near;
        // Perspective: far corners lie on rays from the eye through the near corners.
        const double scale = perspective ? d / kOffCentre.near : 1;
        const glm::dvec4 view(scale * (right ? kOffCentre.right : kOffCentre.left),
                              scale * (top ? kOffCentre.top : kOffCentre.bottom), s * d, 1);
        const glm::dvec4 clip = m * view;
        const Vec3 ndc = Vec3(clip) / clip.w;
        const std::string what = name(c) + (perspective ? " perspective" : " ortho") + " corner " + std::to_string(corner);
        EXPECT_NEAR(ndc.x, right ? 1 : -1, 1e-12) << what;
        EXPECT_NEAR(ndc.y, top ? 1 : -1, 1e-12) << what;
        EXPECT_NEAR(ndc.z, far ? 1 : low, 1e-12) << what;
        EXPECT_GT(clip.w, 0) << what;
      }
    }
  }
}

// --- three.js, written out independently ------------------------------------------------------

// three.js PerspectiveCamera.updateProjectionMatrix (zoom 1, no view offset, WebGL coordinates):
// top = near·tan(DEG2RAD·0.5·fov), height = 2·top, width = aspect·height, left = −width/2,
// makePerspective(left, left + width, top, top − height, near, far). Returns Matrix4.elements.
std::array<double, 16> threePerspective(double fovDeg, double aspect, double near, double far) {
  const double top = near * std::tan(M_PI / 180 * 0.5 * fovDeg);
  const double height = 2 * top, width = aspect * height, left = -0.5 * width;
  const double right = left + width, bottom = top - height;
  const double x = 2 * near / (right - left), y = 2 * near / (top - bottom);
  const double a = (right + left) / (right - left), b = (top + bottom) / (top - bottom);
  const double c = -(far + near) / (far - near), d = -2 * far * near / (far - near);
  // Matrix4.set(row-major) stores column-major elements.
  return {x, 0, 0, 0, 0, y, 0, 0, a, b, c, -1, 0, 0, d, 0};
}

// OrthographicCamera(−h·aspect/2, h·aspect/2, h/2, −h/2, near, far).updateProjectionMatrix().
std::array<double, 16> threeOrthographic(double h, double aspect, double near, double far) {
  const double left = -h * aspect / 2, right = h * aspect / 2, top = h / 2, bottom = -h / 2;
  const double w = 1 / (right - left), hh = 1 / (top - bottom), p = 1 / (far - near);
  const double x = (right + left) * w, y = (top + bottom) * hh, z = (far + near) * p;
  return {2 * w, 0, 0, 0, 0, 2 * hh, 0, 0, 0, 0, -2 * p, 0, -x, -y, -z, 1};
}

// Matrix4.lookAt(eye, target, up) is the camera's rotation; matrixWorldInverse is the inverse of
// compose(position, rotation). Returns that inverse.
Mat4 threeViewMatrix(const Vec3& eye, const Vec3& target, const Vec3& up) {
  const Vec3 z = glm::normalize(eye - target);
  const Vec3 x = glm::normalize(glm::cross(up, z));
  const Vec3 y = glm::cross(z, x);
  Mat4 world(1.0);
  world[0] = glm::dvec4(x, 0);
  world[1] = glm::dvec4(y, 0);
  world[2] = glm::dvec4(z, 0);
  world[3] = glm::dvec4(eye, 1);
  return glm::inverse(world);
}

Camera testCamera(Camera::Projection projection) {
  Camera camera;
  camera.position = Vec3(2.78, 2.73, -8.0);
  camera.target = Vec3(2.6, 2.5, 0.0);
  camera.up = Vec3(0, 1, 0);
  camera.projection = projection;
  camera.fovYDeg = 39.3;
  camera.height = 6;
  camera.near = 0.1;
  camera.far = 40;
  return camera;
}

TEST(CameraProjection, EqualsThreeJsCameraElementByElement) {
  const int width = 640, height = 480;
  for (auto projection : {Camera::Projection::Perspective, Camera::Projection::Orthographic}) {
    const Camera camera = testCamera(projection);
    const CameraProjection ours(camera, width, height);
    const double aspect = double(width) / height;
    const std::array<double, 16> three = projection == Camera::Projection::Perspective
                                             ? threePerspective(camera.fovYDeg, aspect, camera.near, camera.far)
                                             : threeOrthographic(camera.height, aspect, camera.near, camera.far);
    const double* elements = glm::value_ptr(ours.projection());
    for (int k = 0; k < 16; ++k) EXPECT_NEAR(elements[k], three[k], 1e-12) << "projection element " << k;
    const Mat4 threeView = threeViewMatrix(camera.position, camera.target, camera.up);
    expectMatrixNear(ours.view(), threeView, 1e-12, "view");

    // Vector3.project(camera) then the usual NDC → pixel (y down).
    for (const Vec3& p : {Vec3(1, 1, 2), Vec3(4.5, 0.2, 5.5), Vec3(2.78, 5.48, 2.8)}) {
      Mat4 threeProjection;
      for (int k = 0; k < 16; ++k) glm::value_ptr(threeProjection)[k] = three[k];
      const glm::dvec4 clip = threeProjection * threeView * glm::dvec4(p, 1);
      const Vec2 pixel((clip.x / clip.w + 1) / 2 * width, (1 - clip.y / clip.w) / 2 * height);
      const auto ourPixel = ours.toPixel(p);
      ASSERT_TRUE(ourPixel);
      EXPECT_NEAR(ourPixel->x, pixel.x, 1e-9);
      EXPECT_NEAR(ourPixel->y, pixel.y, 1e-9);
    }
  }
}

// --- Pixels and rays ---------------------------------------------------------------------------

TEST(CameraProjection, PixelCentresAndNdcCorners) {
  EXPECT_EQ(ndcToPixel(Vec2(-1, 1), 64, 48), Vec2(0, 0));
  EXPECT_EQ(ndcToPixel(Vec2(1, -1), 64, 48), Vec2(64, 48));
  const Vec2 centre = pixelToNdc(Vec2(0.5, 0.5), 64, 48);
  EXPECT_DOUBLE_EQ(centre.x, -1 + 1.0 / 64);
  EXPECT_DOUBLE_EQ(centre.y, 1 - 1.0 / 48);
}

TEST(CameraProjection, RayThroughAPixelProjectsBackToThatPixelInEveryConvention) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (auto projection : {Camera::Projection::Perspective, Camera::Projection::Orthographic}) {
    const Camera camera = testCamera(projection);
    std::vector<CameraProjection> views;
    for (ClipConvention c : kConventions) views.emplace_back(camera, 97, 61, c);
    for (int trial = 0; trial < 200; ++trial) {
      const Vec2 pixel(97 * unit(random), 61 * unit(random));
      const CameraProjection::Ray ray = views[0].rayThrough(pixel);
      for (const CameraProjection& view : views) {
        for (double s : {0.0, 0.01, 0.37, 1.0}) {
          const auto back = view.toPixel(ray.origin + s * ray.dir);
          ASSERT_TRUE(back);
          EXPECT_NEAR(back->x, pixel.x, 1e-7);
          EXPECT_NEAR(back->y, pixel.y, 1e-7);
        }
        // Every convention puts the ray's ends on its own near and far planes.
        const double low = view.convention().depth == DepthRange::ZeroToOne ? 0 : -1;
        EXPECT_NEAR(view.toNdc(ray.origin)->z, low, 1e-7);
        EXPECT_NEAR(view.toNdc(ray.origin + ray.dir)->z, 1, 1e-7);
      }
      // The near point sits at distance near along the view direction.
      const Vec3 forward = glm::normalize(camera.target - camera.position);
      EXPECT_NEAR(glm::dot(ray.origin - camera.position, forward), camera.near, 1e-9);
    }
  }
}

TEST(CameraProjection, PixelOfRefusesPointsOutsideTheImageOrDepthRange) {
  const CameraProjection view(testCamera(Camera::Projection::Perspective), 64, 48);
  EXPECT_TRUE(view.pixelOf(Vec3(2.78, 2.73, 0)));
  EXPECT_FALSE(view.pixelOf(Vec3(2.78, 2.73, -9)));   // behind the eye
  EXPECT_FALSE(view.pixelOf(Vec3(2.78, 2.73, 40)));   // beyond far
  EXPECT_FALSE(view.pixelOf(Vec3(60, 2.73, 0)));      // off to the side
  const CameraProjection::Ray ray = view.rayThrough(Vec2(10.5, 20.5));
  const auto centre = view.pixelOf(ray.origin + 0.5 * ray.dir);
  ASSERT_TRUE(centre);
  EXPECT_EQ(centre->i, 10);
  EXPECT_EQ(centre->j, 20);
}

TEST(CameraProjection, RefusesDegenerateCamerasAndSizes) {
  const Camera camera = testCamera(Camera::Projection::Perspective);
  EXPECT_THROW(CameraProjection(camera, 0, 10), std::invalid_argument);
  EXPECT_THROW(CameraProjection(camera, 10, -1), std::invalid_argument);
  Camera bad = camera;
  bad.near = 0;
  EXPECT_THROW(CameraProjection(bad, 10, 10), std::invalid_argument);
  bad = camera;
  bad.fovYDeg = 180;
  EXPECT_THROW(CameraProjection(bad, 10, 10), std::invalid_argument);
  bad = camera;
  bad.up = camera.target - camera.position;
  EXPECT_THROW(CameraProjection(bad, 10, 10), std::invalid_argument);
}

TEST(CameraProjection, DefaultCameraSeesTheWholeBounds) {
  const Bounds bounds{Vec3(-3, 0, -2.5), Vec3(3, 3, 2.5)};
  const CameraProjection view(defaultCamera(bounds), 64, 64);
  for (int corner = 0; corner < 8; ++corner) {
    const Vec3 p((corner & 1) ? bounds.max.x : bounds.min.x, (corner & 2) ? bounds.max.y : bounds.min.y,
                 (corner & 4) ? bounds.max.z : bounds.min.z);
    EXPECT_TRUE(view.pixelOf(p)) << "corner " << corner;
  }
}

}  // namespace
}  // namespace penumbra
