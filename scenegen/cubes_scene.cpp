#include "scenegen/cubes_scene.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>

#include "scenegen/scene_parts.h"

namespace penumbra {

namespace {

// Lengths are multiples of 1/64 m so that sums of heights are exact in double
// (contact must be exact: it is what produces D0 edges).
constexpr double kUnit = 1.0 / 64;
constexpr double kRoomHeight = 3.0;
constexpr double kFloorAreaPerObject = 6.0;  // m² per object: ~25% of the floor covered
constexpr double kMinRoomSide = 5.0;
constexpr double kBaseLightSide = 1.5;
constexpr double kLightDrop = 1 * kUnit;     // light just below the ceiling
constexpr double kTiltDeg = 25.0;
constexpr double kMaxObjectTop = 2.0;        // stacks stay well below the lights
constexpr double kGap = 4 * kUnit;           // clearance between footprints and walls
constexpr int kCubePlacementTries = 20000;

// Footprint of an object standing in the room: a disc that contains it.
struct Footprint {
  double x = 0, z = 0, radius = 0;
};

struct Cube {
  double x = 0, z = 0, angleDeg = 0;
  double size = 0, base = 0;  // y of the bottom face
  bool covered = false;       // another cube rests on it
  size_t root = 0;            // index of the floor footprint its stack stands on
};

// Distance from point p to the segment a→b (in xz).
double segmentDistance(double px, double pz, double ax, double az, double bx, double bz) {
  const double abx = bx - ax, abz = bz - az;
  const double t =
      std::clamp(((px - ax) * abx + (pz - az) * abz) / std::max(abx * abx + abz * abz, 1e-300), 0.0, 1.0);
  return std::hypot(px - (ax + t * abx), pz - (az + t * abz));
}

// A multiple of kUnit in [lo, hi] (both multiples of kUnit).
double units(std::mt19937_64& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng) * kUnit;
}

// A square light of side `side` centred at `centre`, facing down, optionally
// tilted by kTiltDeg about `tiltAxis` (through its centre).
Light makeLight(const std::string& id, const Vec3& centre, double side, bool tilted,
                const Vec3& tiltAxis) {
  return squareCeilingLight(id, centre, side, tilted ? kTiltDeg : 0.0, tiltAxis);
}

}  // namespace

CubesRoom cubesRoom(const CubesSceneOptions& options) {
  const double side =
      std::max(kMinRoomSide, std::sqrt(std::max(options.cubes, 0) * kFloorAreaPerObject));
  return CubesRoom{side, kRoomHeight};
}

Scene makeCubesScene(const CubesSceneOptions& options) {
  if (options.cubes < 0) throw std::invalid_argument("makeCubesScene: negative cube count");
  if (!(options.lightScale > 0)) throw std::invalid_argument("makeCubesScene: lightScale must be > 0");
  std::mt19937_64 rng(options.seed);
  const CubesRoom room = cubesRoom(options);
  const double half = room.side / 2, height = room.height;

  // Lights: centred, or two at x = ±side/4; the top edge of a tilted light stays
  // kLightDrop below the ceiling.
  const double lightSide = kBaseLightSide * options.lightScale;
  const double tiltRise = options.tiltedLight ? lightSide / 2 * std::sin(glm::radians(kTiltDeg)) : 0;
  const double lightY = height - kLightDrop - tiltRise;
  if (lightY - tiltRise <= kMaxObjectTop || lightSide / 2 + kGap >= half / (options.twoLights ? 2 : 1))
    throw std::invalid_argument("makeCubesScene: lightScale too large for the room");
  std::vector<Light> lights;
  if (options.twoLights) {
    lights.push_back(makeLight("light", Vec3(-half / 2, lightY, 0), lightSide, options.tiltedLight,
                               Vec3(1, 0, 0)));
    lights.push_back(makeLight("light_2", Vec3(half / 2, lightY, 0), lightSide,
                               options.tiltedLight, Vec3(0, 0, 1)));
    lights.back().radiance = Vec3(8.0, 9.0, 12.0);  // a cooler second light
  } else {
    lights.push_back(
        makeLight("light", Vec3(0, lightY, 0), lightSide, options.tiltedLight, Vec3(1, 0, 0)));
  }

  std::vector<Material> materials{{"white", Vec3(0.8)}, {"clay", Vec3(0.75, 0.45, 0.3)}};

  // The room: six quads facing inwards.
  std::vector<Object> objects = roomObjects(half, half, height);

  std::vector<Footprint> footprints;  // of everything standing on the floor
  std::vector<size_t> objectRoot(objects.size(), SIZE_MAX);  // footprint each object stands on
  std::vector<Cube> cubes;
  auto placeOnFloor = [&](double radius) -> Footprint {
    const double range = half - radius - kGap;
    if (range <= 0) throw std::runtime_error("makeCubesScene: object larger than the room");
    for (int attempt = 0; attempt < kCubePlacementTries; ++attempt) {
      const Footprint f{uniform(rng, -range, range), uniform(rng, -range, range), radius};
      const bool clear = std::all_of(footprints.begin(), footprints.end(), [&](const Footprint& o) {
        return std::hypot(f.x - o.x, f.z - o.z) >= f.radius + o.radius + kGap;
      });
      if (clear) {
        footprints.push_back(f);
        return f;
      }
    }
    throw std::runtime_error("makeCubesScene: could not place an object (room too crowded)");
  };

  for (int i = 0; i < options.cubes; ++i) {
    const double angle = uniform(rng, 0, 90);
    const bool table = uniform(rng, 0, 1) < options.thinTables;
    const bool stacked = !table && uniform(rng, 0, 1) < options.stackedFraction;
    Object object;
    object.material = (i % 2) ? "clay" : "white";

    if (table) {
      // Top w×d, 3/64 thick, on four 3/64-square legs; local origin at the floor.
      const double w = units(rng, 64, 102), d = units(rng, 38, 64);
      const double legHeight = 44 * kUnit, thick = 3 * kUnit, leg = 3 * kUnit, inset = 2 * kUnit;
      const Footprint f = placeOnFloor(std::hypot(w, d) / 2);
      object.id = "table_" + std::to_string(i);
      addBox(object, {-w / 2, legHeight, -d / 2}, {w / 2, legHeight + thick, d / 2});
      for (int sx = -1; sx <= 1; sx += 2)
        for (int sz = -1; sz <= 1; sz += 2) {
          const double cx = sx * (w / 2 - inset - leg / 2), cz = sz * (d / 2 - inset - leg / 2);
          addBox(object, {cx - leg / 2, 0, cz - leg / 2}, {cx + leg / 2, legHeight, cz + leg / 2});
        }
      object.transform.translate = Vec3(f.x, 0, f.z);
      object.transform.rotateDeg = Vec3(0, angle, 0);
      objects.push_back(std::move(object));
      objectRoot.push_back(footprints.size() - 1);
      continue;
    }

    Cube cube;
    cube.angleDeg = angle;
    // Resting on a cube: at most 0.6 of its size, so the rotated footprint (radius
    // size/√2 ≤ 0.43·lower) fits inside the lower top's inscribed circle.
    std::vector<size_t> candidates;
    if (stacked)
      for (size_t c = 0; c < cubes.size(); ++c)
        if (!cubes[c].covered && cubes[c].size >= 32 * kUnit &&
            cubes[c].base + cubes[c].size + 16 * kUnit <= kMaxObjectTop)
          candidates.push_back(c);
    if (!candidates.empty()) {
      Cube& lower = cubes[candidates[std::uniform_int_distribution<size_t>(0, candidates.size() - 1)(rng)]];
      const int maxUnits = int(std::floor(0.6 * lower.size / kUnit));
      const int topUnits = int(std::floor((kMaxObjectTop - lower.base - lower.size) / kUnit));
      cube.size = units(rng, 16, std::max(16, std::min(maxUnits, topUnits)));
      const double slack = lower.size / 2 - cube.size / std::sqrt(2.0);
      const double r = slack * std::sqrt(uniform(rng, 0, 1)), phi = uniform(rng, 0, 2 * M_PI);
      cube.x = lower.x + r * std::cos(phi);
      cube.z = lower.z + r * std::sin(phi);
      cube.base = lower.base + lower.size;
      cube.root = lower.root;
      lower.covered = true;
    } else {
      cube.size = units(rng, 26, 64);
      const Footprint f = placeOnFloor(cube.size / std::sqrt(2.0));
      cube.x = f.x;
      cube.z = f.z;
      cube.base = 0;
      cube.root = footprints.size() - 1;
    }
    cubes.push_back(cube);

    object.id = "cube_" + std::to_string(i);
    addBox(object, Vec3(-0.5), Vec3(0.5));
    object.transform.translate = Vec3(cube.x, cube.base + cube.size / 2, cube.z);
    object.transform.rotateDeg = Vec3(0, cube.angleDeg, 0);
    object.transform.scale = Vec3(cube.size);
    objects.push_back(std::move(object));
    objectRoot.push_back(cube.root);
  }

  if (options.subjectCube) {
    // The subject and its corridor; after every other object so that the main
    // generator's draws (and so the rest of the scene) are the same as without it.
    const double radius = kSubjectSide / std::sqrt(2.0);
    const double x = lights[0].polygon.empty() ? 0 : centroid(lights[0].polygon).x;
    const Vec3 centre(std::round((x + kSubjectLightOffset) / kUnit) * kUnit, kSubjectSide / 2, 0);
    const double travel = std::min(kSubjectTravel, half - radius - kGap - kSubjectMargin);
    if (centre.x + radius + kGap + kSubjectMargin > half || travel <= 0)
      throw std::invalid_argument("makeCubesScene: the room is too small for the subject cube");
    const double corridor = radius + kSubjectMargin;
    auto blocks = [&](const Footprint& f) {
      return segmentDistance(f.x, f.z, centre.x, -travel, centre.x, travel) <
             f.radius + corridor + kGap;
    };
    std::mt19937_64 moveRng(options.seed ^ 0x5b7ec7c0be5eedULL);
    for (size_t k = 0; k < footprints.size(); ++k) {
      if (!blocks(footprints[k])) continue;
      const double range = half - footprints[k].radius - kGap;
      bool moved = false;
      for (int attempt = 0; attempt < kCubePlacementTries && !moved; ++attempt) {
        const Footprint f{uniform(moveRng, -range, range), uniform(moveRng, -range, range),
                          footprints[k].radius};
        bool clear = !blocks(f);
        for (size_t j = 0; clear && j < footprints.size(); ++j)
          clear = j == k || std::hypot(f.x - footprints[j].x, f.z - footprints[j].z) >=
                                f.radius + footprints[j].radius + kGap;
        if (!clear) continue;
        // The stack moves as one: only x and z change, so contacts stay exact.
        for (size_t o = 0; o < objects.size(); ++o)
          if (objectRoot[o] == k) {
            objects[o].transform.translate.x += f.x - footprints[k].x;
            objects[o].transform.translate.z += f.z - footprints[k].z;
          }
        footprints[k] = f;
        moved = true;
      }
      if (!moved)
        throw std::runtime_error("makeCubesScene: could not clear the subject cube's corridor");
    }
    Object subject;
    subject.id = kSubjectCubeId;
    subject.material = "clay";
    addBox(subject, Vec3(-0.5), Vec3(0.5));
    subject.transform.translate = centre;
    subject.transform.rotateDeg = Vec3(0, 20, 0);
    subject.transform.scale = Vec3(kSubjectSide);
    objects.push_back(std::move(subject));
  }

  Camera camera;
  camera.position = Vec3(0, 1.6, half - 0.25);
  camera.target = Vec3(0, 0.5, 0);
  camera.fovYDeg = 60;
  camera.far = 4 * room.side;
  return Scene(std::move(lights), std::move(materials), std::move(objects), camera);
}

CubesSceneOptions mixedCubesOptions(uint64_t seed) {
  CubesSceneOptions options;
  options.cubes = 1 + int(seed % 6);
  options.seed = seed;
  options.lightScale = seed % 3 == 0 ? 0.2 : 1.0;
  options.tiltedLight = seed % 4 == 1;
  options.twoLights = seed % 5 == 2;
  options.stackedFraction = seed % 2 ? 0.4 : 0.0;
  options.thinTables = seed % 6 == 3 ? 0.3 : 0.0;
  return options;
}

}  // namespace penumbra
