#include "protocol/camera_json.h"

#include "protocol/json_reader.h"

namespace penumbra::protocol {

nlohmann::json cameraToJson(const Camera& camera) {
  return Json{{"position", toJson(camera.position)},
              {"target", toJson(camera.target)},
              {"up", toJson(camera.up)},
              {"projection", camera.projection == Camera::Projection::Perspective ? "perspective"
                                                                                  : "orthographic"},
              {"fov_y_deg", camera.fovYDeg},
              {"height", camera.height},
              {"near", camera.near},
              {"far", camera.far}};
}

}  // namespace penumbra::protocol
