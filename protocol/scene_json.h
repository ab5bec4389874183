// Scene JSON v1 (SCENE_FORMAT.md) <-> penumbra::Scene: a validating reader that
// names the key path of the first problem, and an exact writer. Free functions;
// thread-safe (no shared state).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "core/scene/scene.h"
#include "protocol/validation_error.h"

namespace penumbra::protocol {

// Largest polygon (face or light) accepted: validation cost grows with the square
// of a polygon's vertex count, and no sensible scene needs more.
inline constexpr size_t kMaxPolygonVertices = 1024;
// Magnitudes (SCENE_FORMAT.md "Limits"; issue 36): coordinates (object vertices, light corners,
// translations, and every vertex once placed in the world) within ±1e9 m, so products of
// coordinates stay finite in double and Embree's float rays (±1.8e18) can reach them; scale
// factors within ±1e6 (and not 0), rotations within ±1e6 degrees, radiance at most 1e12.
inline constexpr double kMaxCoordinate = 1e9;
inline constexpr double kMaxScale = 1e6;
inline constexpr double kMaxRotationDeg = 1e6;
inline constexpr double kMaxRadiance = 1e12;

struct VolumeFiles;  // protocol/volume_json.h

// Validates the whole document first and throws ValidationError at the first
// problem (in document order: format, version, lights, materials, objects,
// camera); only a valid document becomes a Scene. Materials come out ordered by
// name (a JSON object has no order). Volume objects ("type": "volume") read their NRRD
// through `volumeFiles`; without it they are refused (a scene sent as JSON names no files).
Scene sceneFromJson(const nlohmann::json& root, const VolumeFiles* volumeFiles = nullptr);

// Writes v1 with full double precision; sceneFromJson(sceneToJson(s)) == s
// (materials ordered by name; volume objects after the polygon objects, their files
// as resolved absolute paths). The camera is written with both fov_y_deg and
// height so that it round-trips whole.
nlohmann::json sceneToJson(const Scene& scene);

// The parts an edit reuses (SCENE_FORMAT.md "Edit scripts"). objectFromJson
// validates one object at `path` against the given materials (all checks except
// id uniqueness, which needs the surrounding list).
Object objectFromJson(const nlohmann::json& value, const std::string& path,
                      const std::vector<Material>& materials);
Transform transformFromJson(const nlohmann::json& value, const std::string& path);
nlohmann::json objectToJson(const Object& object);
nlohmann::json transformToJson(const Transform& transform);
// A light's polygon (3..kMaxPolygonVertices finite points, planar, convex) and radiance
// (finite, ≥ 0) at `path`, as in a scene's lights (set_light reuses them).
Polygon3 lightPolygonFromJson(const nlohmann::json& value, const std::string& path);
Vec3 radianceFromJson(const nlohmann::json& value, const std::string& path);
nlohmann::json polygonToJson(const Polygon3& polygon);
// One light at `path` as in a scene's lights ({"id", "polygon", "radiance"}; add_light
// reuses them). Id uniqueness needs the surrounding list: the caller's check.
Light lightFromJson(const nlohmann::json& value, const std::string& path);
nlohmann::json lightToJson(const Light& light);

// Files: limits from protocol/json_text.h (64 MiB, nesting depth 64); size,
// depth and syntax errors are ValidationErrors with path `(json)`; a file that
// cannot be read or written is a std::runtime_error.
// Volume files resolve against the scene file's folder.
Scene loadSceneFile(const std::string& path);
void saveSceneFile(const Scene& scene, const std::string& path);

}  // namespace penumbra::protocol
