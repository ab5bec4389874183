// How far a display mesh's interpolated direct light is from the exact reference over a view:
// per pixel of the camera's view, the irradiance the mesh interpolates at the pixel's surface
// point against ExactReference there, counted against the scene's bright level. Pure
// functions of their arguments; thread-safe.
#pragma once

#include <cstddef>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/raycast/camera_projection.h"
#include "core/scene/scene.h"
#include "core/util/parallel.h"

namespace penumbra {

// A pixel off by more than 1 % of the bright level: where, and its local unshadowed level (the
// largest channel of what every light would give there with nothing in the way: the scale the
// display mesh's tolerance is relative to).
struct DirectLightMiss {
  int x = 0, y = 0;
  uint32_t face = 0;  // Scene::faces() index
  Vec3 position{0.0};
  double exact = 0, mesh = 0, unshadowed = 0;  // largest channel
};

struct DirectLightError {
  size_t pixels = 0;        // surface pixels on faces that receive light
  double brightLevel = 0;   // 99th percentile of the exact irradiance's largest channel there
  // Pixels whose |mesh − exact| (largest channel) exceeds 1 %, 2 % of the bright level.
  size_t overOnePercent = 0, overTwoPercent = 0;
  // Of those over 1 %, the pixels brighter than the bright level itself (the top 1 %, clipped
  // white at the page's and the renderer's automatic exposure).
  size_t overOnePercentAboveBright = 0;
  double worstRelative = 0;  // the largest |mesh − exact| / brightLevel
  int worstX = -1, worstY = -1;
  double worstMesh = 0, worstExact = 0;  // largest channel at the worst pixel
  std::vector<DirectLightMiss> misses;    // the pixels over 1 %, in row order
};

// The view's surface pixels (first front-facing face, as the renderer's rays see them) on
// receiving faces: the mesh's interpolation (MeshLookup) against the exact reference.
DirectLightError directLightError(const Scene& scene, const Mesh& mesh, const Camera& camera, int width,
                                  int height, const Parallel& parallel);

}  // namespace penumbra
