// Building blocks shared by the seeded scene generators: boxes, room quads and
// square ceiling lights. Pure functions on values; thread-safe.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

// A uniform double in [lo, hi) from the generator's seeded engine.
inline double uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Appends an axis-aligned box (8 vertices, 6 outward quads) to an object.
void addBox(Object& object, const Vec3& lo, const Vec3& hi);

// Appends a UV sphere (stacks ≥ 2 latitude bands × slices ≥ 3 longitudes: a triangle fan
// round each pole, planar quads between, all outward) to an object.
void addUvSphere(Object& object, const Vec3& centre, double radius, int stacks, int slices);

// A one-quad static "white" object whose front faces `front`.
Object quadObject(const std::string& id, const Polygon3& quad, const Vec3& front);

// The six inward quads of the room [-halfX, halfX] × [0, height] × [-halfZ, halfZ]:
// "floor", "ceiling", "wall_n", "wall_s", "wall_e", "wall_w".
std::vector<Object> roomObjects(double halfX, double halfZ, double height);

// A square light of side `side` centred at `centre`, facing down, radiance 10,
// tilted by `tiltDeg` about the unit `tiltAxis` through its centre.
Light squareCeilingLight(const std::string& id, const Vec3& centre, double side, double tiltDeg,
                         const Vec3& tiltAxis);

}  // namespace penumbra
