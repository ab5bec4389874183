// The default studio a model without lights is imported into: the 6 × 3 × 6 m room of the
// benchmarks (floor at y = 0, walls, ceiling) under one 1 m² light, the model scaled to fit
// and resting on the floor at the room's centre. Pure functions on values; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/geom/vec.h"
#include "core/scene/scene.h"

namespace penumbra::interchange {

// The room is [-3, 3] × [0, 3] × [-3, 3] (y up); the light a 1 m square facing down,
// centred 1/64 m under the ceiling (out of the ceiling's plane), radiance 10 unless given.
inline constexpr double kStudioHalfSide = 3.0;
inline constexpr double kStudioHeight = 3.0;
inline constexpr double kStudioLightSide = 1.0;
inline constexpr double kStudioLightY = kStudioHeight - 1.0 / 64;
inline constexpr double kStudioRadiance = 10.0;
// A model whose largest extent lies in [kStudioMinFit, kStudioMaxFit] keeps its size; any
// other is scaled uniformly to kStudioFitExtent (inches, millimetres, kilometres alike).
inline constexpr double kStudioMinFit = 0.1;
inline constexpr double kStudioMaxFit = 2.0;
inline constexpr double kStudioFitExtent = 1.0;

// The room's box: [-3, 3] × [0, 3] × [-3, 3].
inline Bounds studioBounds() {
  return Bounds{Vec3(-kStudioHalfSide, 0, -kStudioHalfSide),
                Vec3(kStudioHalfSide, kStudioHeight, kStudioHalfSide)};
}

// Where the model goes: studio position = (model position − anchor) × scale, so the anchor (the
// middle of the model's bounds' bottom) lands on the floor's centre, digits kept however far off
// the model was modelled.
struct StudioPlacement {
  double scale = 1;
  Vec3 anchor{0.0};
  double extentBefore = 0;  // the model's largest extent, in its own (already --scale'd) units

  Vec3 apply(const Vec3& p) const { return (p - anchor) * scale; }
  Vec3 offset() const { return -anchor * scale; }  // the same as position × scale + offset()
};

// `model`: the bounds of every vertex a face uses. Centred on the floor's centre, its lowest
// point on the floor (y = 0).
StudioPlacement placeInStudio(const Bounds& model);

// The studio's pieces as scene v1 JSON (docs/SCENE_FORMAT.md). Ids are given by the caller so
// they can be made unique against the model's own.
nlohmann::json studioLight(const std::string& id, const Vec3& radiance);
// Six static quads facing into the room, in the order floor, ceiling, walls n, s, e, w, with
// ids `prefix` + "floor", … and material `material`.
nlohmann::json studioRoom(const std::string& prefix, const std::string& material);
// A view from the room's south side at eye height, looking at the placed model's centre.
nlohmann::json studioCamera(const Bounds& placedModel);
// The one-sentence account for the import report, e.g. "no lights in teapot.obj: placed it in
// the default studio (6 × 3 × 6 m room, 1 m² light just under the 3 m ceiling), scaled by
// 0.0254 (largest extent 39.37 → 1 m), resting on the floor at the room's centre".
std::string studioSentence(const std::string& source, const StudioPlacement& placement);

}  // namespace penumbra::interchange
