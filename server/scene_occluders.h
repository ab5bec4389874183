// The DM's occluder lists a version keeps for images: per microfacet receiver a frozen
// OccluderIndex (core/dmtree/occluder_index.h), shared between versions while the receiver is
// unchanged. Made by the session under its edit lock; read by /image from the snapshot alone.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "core/dmtree/occluder_index.h"
#include "core/engine/engine.h"

namespace penumbra::server {

using OccluderIndexes = std::map<FaceId, std::shared_ptr<const OccluderIndex>>;

// True when the face's object has a microfacet material (the camera sees its BSDF, which needs
// the visible light pieces; a diffuse face only needs its mesh values).
bool seenThroughBsdf(const Scene& scene, FaceId face);

// The indexes of the engine's microfacet receivers: those in `redo` (or missing from
// `previous`) frozen afresh from their trees, the others taken from `previous`.
struct FrozenOccluders {
  OccluderIndexes indexes;
  size_t frozen = 0;   // receivers frozen afresh
  double seconds = 0;  // time spent freezing
};
FrozenOccluders freezeOccluders(const Engine& engine, const OccluderIndexes& previous,
                                const std::set<FaceId>& redo);

// RenderSettings::occluders reading the indexes (kept alive by the returned function).
std::function<void(FaceId, const Vec3&, size_t, std::vector<FaceId>&)> occluderLookup(
    std::shared_ptr<const OccluderIndexes> indexes);

}  // namespace penumbra::server
