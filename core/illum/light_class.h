// Whether a point sees a light wholly, partly or not at all (the vertex classes of the mesh
// format): one enum and how classes combine over lights. Plain values; thread-safe.
#pragma once

#include <cstdint>

namespace penumbra {

// Visibility of the lights from a point (SCENE_FORMAT.md "class").
enum class LightClass : uint8_t { Lit, Penumbra, Umbra };

const char* toString(LightClass c);

// Combines the classes of one point over several lights.
LightClass combine(LightClass a, LightClass b);

}  // namespace penumbra
