// The one tolerance policy of core: every geometric epsilon is a fraction of the
// scene's size (its bounding-box diagonal). Plain value; thread-safe.
#pragma once

namespace penumbra {

struct Tolerance {
  // Size of the scene: the diagonal of its bounding box (lights included).
  double sceneSize = 1.0;

  // "A face whose plane contains p never shadows p" uses this distance
  // (SCENE_FORMAT.md: within 1e-6 of the scene's diagonal).
  double onPlane() const { return 1e-6 * sceneSize; }
  // Geometric predicates (clipping, point classification, vertex merging).
  double length() const { return 1e-9 * sceneSize; }
  // Areas below this are treated as empty.
  double area() const { return 1e-18 * sceneSize * sceneSize; }
  // A face with a vertex farther than this from its plane is projected onto it
  // (Scene::faces()): 1e-3 of length(), so predicates at length() see it flat; the
  // rounding of an exactly planar face is far below and left as authored.
  double snap() const { return 1e-12 * sceneSize; }
  // The thinnest face a scene may hold (polygon.h width()): a thinner one lies within
  // onPlane() of a line, so which side of it a point is on is not decided reliably,
  // and 2D predicates at length() would merge its long sides.
  double minFaceWidth() const { return onPlane(); }

  static Tolerance forSize(double size) { return Tolerance{size > 0 ? size : 1.0}; }
};

// Face validity relative to the face's own size (SCENE_FORMAT.md: planar within
// 1e-6 of the face's size).
inline constexpr double kRelativePlanarity = 1e-6;

}  // namespace penumbra
