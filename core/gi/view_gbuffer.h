// The G-buffer of a plain view: per pixel the first front-facing face and its point, as the
// renderer's camera rays see them (lights are not in the RayScene, so they are not surfaces).
// The renderer builds its own (it also drops pixels where a light or a microfacet surface is in
// front); checks and benches use this one.
#pragma once

#include "core/gi/sensor_gi.h"
#include "core/raycast/camera_projection.h"
#include "core/raycast/ray_scene.h"
#include "core/util/parallel.h"

namespace penumbra::gi {

GBuffer viewGBuffer(const RayScene& rays, const Camera& camera, int width, int height, const Parallel& parallel);

}  // namespace penumbra::gi
