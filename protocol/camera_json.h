// A scene's camera as scene v1 writes it ({"position", "target", "up", "projection", "fov_y_deg",
// "height", "near", "far"}: both fov_y_deg and height, so that it round-trips whole). The reader
// is part of sceneFromJson (its limits depend on the scene's bounds). Free function; thread-safe.
#pragma once

#include <nlohmann/json.hpp>

#include "core/scene/scene.h"

namespace penumbra::protocol {

nlohmann::json cameraToJson(const Camera& camera);

}  // namespace penumbra::protocol
