// The exactly visible light pieces a microfacet point integrates over, from the DM: the cell's
// occluder list (Engine::Receiver::tree) fed to a Backprojection. Shared by render(), the CLI
// and the microfacet bench. Pure functions; the returned callables borrow their arguments and are
// thread-safe while those stay alive and unchanged.
#pragma once

#include <functional>
#include <vector>

#include "core/engine/engine.h"
#include "core/render/microfacet_shading.h"

namespace penumbra {

// The faces that can hide light `light` from p on receiving face `face` (appended to out).
using OccludersFn =
    std::function<void(FaceId face, const Vec3& p, size_t light, std::vector<FaceId>& out)>;

// The occluder list of the DM cell containing p (light-plane pseudo-occluders left out);
// nothing for a face that is not a receiver.
OccludersFn dmOccluderLists(const Engine& engine);

// The visible pieces of a light: a Backprojection of the faces `occluders` names.
VisiblePiecesFn backprojectedPieces(const Scene& scene, OccludersFn occluders);

}  // namespace penumbra
