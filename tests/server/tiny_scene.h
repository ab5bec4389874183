// A floor, a box and a lamp as scene JSON: builds and renders in milliseconds, for server tests
// that need many scenes or frames (camera limits, journal faults).
#pragma once

#include <nlohmann/json.hpp>

namespace penumbra::server::test {

inline nlohmann::json tinyScene() {
  return nlohmann::json::parse(R"({
  "format": "penumbra.scene", "version": 1,
  "lights": [{"id": "lamp", "radiance": [10, 10, 10],
              "polygon": [[-0.5, 2.9, -0.5], [0.5, 2.9, -0.5], [0.5, 2.9, 0.5], [-0.5, 2.9, 0.5]]}],
  "objects": [
    {"id": "floor", "vertices": [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]], "faces": [[0, 1, 2, 3]]},
    {"id": "box", "transform": {"translate": [0, 0.5, 0]},
     "vertices": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],
                  [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],
     "faces": [[0,3,2,1],[4,5,6,7],[0,4,7,3],[1,2,6,5],[0,1,5,4],[3,7,6,2]]}]
})");
}

}  // namespace penumbra::server::test
