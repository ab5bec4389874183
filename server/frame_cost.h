// The work a frame of edits will cost, estimated before it starts from its light and face
// counts, and the limit past which it is refused (docs/API.md "Limits"). A light added or
// reshaped lights every receiver again among every light's discontinuities, so its cost grows
// with the faces and the lights after the frame; an added object is lit by every light. Pure.
#pragma once

#include <cstdint>
#include <string>

#include "core/engine/frame.h"
#include "core/scene/scene.h"

namespace penumbra::server {

struct FrameCost {
  uint64_t lightChanges = 0;  // add_light, set_light with a polygon
  uint64_t facesAdded = 0;    // faces of added objects
  uint64_t lightsAfter = 0, facesAfter = 0;
  // lightChanges × lightsAfter × facesAfter + facesAdded × lightsAfter
  uint64_t work() const;
  std::string describe() const;  // the product written out, for the refusal
};

FrameCost estimateFrameCost(const Scene& scene, const Frame& frame);

// Throws ApiError 422 frame_too_costly at `edits`, naming the estimate and the limit, when the
// frame's work is past `maxWork`.
void refuseCostlyFrame(const FrameCost& cost, uint64_t maxWork);

}  // namespace penumbra::server
