// Shared by the fuzz targets: the tiny scene they edit and serve, and how a target reports a
// broken invariant. Header-only; every function is thread-safe.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/scene/scene.h"
#include "interchange/scene_import.h"
#include "protocol/scene_json.h"

namespace penumbra::fuzz {

// A floor, two unit cubes and a lamp: builds in milliseconds, so one input stays fast.
inline constexpr std::string_view kTinySceneJson = R"({
  "format": "penumbra.scene", "version": 1,
  "lights": [{"id": "lamp", "radiance": [10, 10, 10],
              "polygon": [[-0.5, 2.9, -0.5], [0.5, 2.9, -0.5], [0.5, 2.9, 0.5], [-0.5, 2.9, 0.5]]}],
  "materials": {"white": {"albedo": [0.8, 0.8, 0.8]}, "red": {"albedo": [0.7, 0.1, 0.1]}},
  "objects": [
    {"id": "floor", "material": "white", "static": true,
     "vertices": [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]], "faces": [[0, 1, 2, 3]]},
    {"id": "box", "material": "red",
     "transform": {"translate": [0, 0.5, 0], "rotate_deg": [0, 30, 0], "scale": [1, 1, 1]},
     "vertices": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],
                  [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],
     "faces": [[0,3,2,1],[4,5,6,7],[0,4,7,3],[1,2,6,5],[0,1,5,4],[3,7,6,2]]},
    {"id": "box2", "material": "white", "transform": {"translate": [1.5, 0.25, 0.5], "scale": [0.5, 0.5, 0.5]},
     "vertices": [[-0.5,-0.5,-0.5],[0.5,-0.5,-0.5],[0.5,0.5,-0.5],[-0.5,0.5,-0.5],
                  [-0.5,-0.5,0.5],[0.5,-0.5,0.5],[0.5,0.5,0.5],[-0.5,0.5,0.5]],
     "faces": [[0,3,2,1],[4,5,6,7],[0,4,7,3],[1,2,6,5],[0,1,5,4],[3,7,6,2]]}
  ]
})";

inline const Scene& tinyScene() {
  static const Scene scene = protocol::sceneFromJson(nlohmann::json::parse(kTinySceneJson));
  return scene;
}

// A broken invariant is a finding: print it and abort so libFuzzer keeps the input.
[[noreturn]] inline void fail(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant broken: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void check(bool ok, const std::string& what) {
  if (!ok) fail(what);
}

// PENUMBRA_FUZZ_STRICT=1: also count as findings the failures already known and handled by
// other work (internal errors inside Engine::apply, HTTP 500 answers); see README "Fuzzing".
inline bool strict() {
  static const bool on = [] {
    const char* v = std::getenv("PENUMBRA_FUZZ_STRICT");
    return v && std::string_view(v) == "1";
  }();
  return on;
}

// PENUMBRA_FUZZ_VERBOSE=1: say what became of each input (to check that seeds get deep).
inline void note(const std::string& what) {
  static const bool on = [] {
    const char* v = std::getenv("PENUMBRA_FUZZ_VERBOSE");
    return v && std::string_view(v) == "1";
  }();
  if (on) std::fprintf(stderr, "  %s\n", what.c_str());
}

// What every import target checks of an accepted file: its report serialises and its scene
// JSON reads back as the imported scene.
inline void checkImport(const interchange::ImportResult& result) {
  (void)result.report.toJson().dump();
  check(protocol::sceneToJson(protocol::sceneFromJson(result.sceneJson)) ==
            protocol::sceneToJson(result.scene),
        "imported scene JSON does not read back as the imported scene");
  note("imported " + std::to_string(result.scene.faces().size()) + " faces");
}

}  // namespace penumbra::fuzz
