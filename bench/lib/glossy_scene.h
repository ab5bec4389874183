// The microfacet bench's scene (issue 13, step 5): a glossy conductor floor under one
// rectangular light, a box floating between them whose wide penumbra crosses the floor's
// highlight as the camera sees it. Pure; thread-safe.
#pragma once

#include "core/scene/scene.h"

namespace penumbra {

struct GlossySceneOptions {
  double roughness = 0.3;         // GGX α of the floor (isotropic)
  bool singleScattering = false;  // the floor's BSDF: first bounce only (eval is then exact)
};

// Floor [-3, 3]² at y = 0 ("floor", material "glossy_floor": a copper-like conductor); box
// "blocker" [-0.45, 0.45] × [1.0, 1.3] × [0.55, 1.45] (diffuse "white"); light "panel"
// 1.4 × 0.8 m at y = 2.5 facing down, radiance 20; a camera at (0, 2.2, 5) looking at
// (0, 0, 1.2).
Scene makeGlossyScene(const GlossySceneOptions& options = {});

}  // namespace penumbra
