// Seeded generator of benchmark and property-test scenes: a closed room lit by one
// or two ceiling lights, with cubes (some stacked) and tables. Pure function; thread-safe.
#pragma once

#include <cstdint>

#include "core/scene/scene.h"

namespace penumbra {

struct CubesSceneOptions {
  int cubes = 15;               // objects standing in the room (cubes and tables)
  uint64_t seed = 1;
  double lightScale = 1.0;      // light side factor: 0.2 = a light 5× smaller
  double stackedFraction = 0.2; // share of cubes resting on another cube's top
  bool tiltedLight = false;     // tilt the light(s) by 25°, still facing down-ish
  bool twoLights = false;
  double thinTables = 0.0;      // share of objects that are tables (slab on 4 legs)
  // Adds kSubjectCubeId: the same cube at every count and seed (see below), with
  // its drag corridor kept clear. Off: the scene is exactly as without the field.
  bool subjectCube = false;
};

// The subject cube (CubesSceneOptions::subjectCube): a 0.5 m cube standing on the
// floor, centre kSubjectLightOffset m along +x from the first light's centre,
// turned 20° about y, material "clay", not static, listed after every other
// object. Its corridor — the segment kSubjectTravel m both ways along z (tangential
// to the circle round the light; clipped to stay kSubjectMargin + 1/16 m inside
// the walls), widened by its footprint radius + kSubjectMargin — is kept clear:
// every floor object (with whatever is stacked on it) whose footprint comes within
// 1/16 m of the corridor is moved to a free spot drawn from a second seeded
// generator; everything else is exactly where it is without the subject.
inline constexpr const char* kSubjectCubeId = "cube_subject";
inline constexpr double kSubjectSide = 0.5;
inline constexpr double kSubjectLightOffset = 1.5;
inline constexpr double kSubjectTravel = 8.0;  // 100 drag frames of 8 cm
inline constexpr double kSubjectMargin = 0.05;

// The room is centred on x = z = 0 with its floor at y = 0; its side grows with
// sqrt(cubes) so the floor density stays the same from 15 to 5000 objects.
// Sizes and heights are multiples of 1/64 m, so "resting on" is exact in double:
// cube bottoms lie exactly at y = 0 or exactly at the top of the cube below.
// Object ids: "floor", "ceiling", "wall_n", "wall_s", "wall_e", "wall_w",
// "cube_<i>", "table_<i>" (and kSubjectCubeId); lights "light" (and "light_2"); materials "white", "clay".
// Every object is placed with a transform (translate, rotate about y, scale).
Scene makeCubesScene(const CubesSceneOptions& options);

// The mix of options the property tests sweep, one scene per seed: 1–6 cubes, a
// light 5× smaller on every third seed, tilted on every fourth, two lights on every
// fifth, stacked cubes on odd seeds, tables on every sixth.
CubesSceneOptions mixedCubesOptions(uint64_t seed);

// Room dimensions used by makeCubesScene (for tests and benchmark reports).
struct CubesRoom {
  double side = 0;    // floor is [-side/2, side/2]² in x and z
  double height = 0;  // ceiling at y = height
};
CubesRoom cubesRoom(const CubesSceneOptions& options);

}  // namespace penumbra
