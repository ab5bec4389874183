// Seeded non-convex meshes for the chain tests (issue 35): closed, open, with flipped
// faces. Triangles in world space, counter-clockwise seen from outside.
#pragma once

#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra::test {

// A UV sphere of `stacks` × 2·`stacks` with each ring's radius scaled by a seeded bump
// in [1 − bump, 1 + bump] (bump 0: convex); closed, poles as triangle fans.
inline Object bumpySphere(const std::string& id, Vec3 centre, double radius, int stacks, double bump, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(1 - bump, 1 + bump);
  const int slices = 2 * stacks;
  Object o;
  o.id = id;
  o.vertices.push_back(centre + Vec3(0, radius, 0));
  for (int i = 1; i < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      const double theta = M_PI * i / stacks, phi = 2 * M_PI * j / slices, r = radius * u(rng);
      o.vertices.push_back(centre + r * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta), std::sin(theta) * std::sin(phi)));
    }
  o.vertices.push_back(centre - Vec3(0, radius, 0));
  auto at = [&](int i, int j) { return 1 + (i - 1) * slices + (j % slices); };
  const int bottom = int(o.vertices.size()) - 1;
  for (int j = 0; j < slices; ++j) o.faces.push_back({0, at(1, j + 1), at(1, j)});
  for (int i = 1; i + 1 < stacks; ++i)
    for (int j = 0; j < slices; ++j) {
      o.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      o.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (int j = 0; j < slices; ++j) o.faces.push_back({bottom, at(stacks - 1, j), at(stacks - 1, j + 1)});
  return o;
}

// A torus around the vertical axis (closed, genus 1), tube bumped as bumpySphere's rings.
inline Object torus(const std::string& id, Vec3 centre, double major, double minor, int rings, int sides, double tilt) {
  Object o;
  o.id = id;
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      const double a = 2 * M_PI * i / rings, b = 2 * M_PI * j / sides;
      const Vec3 p((major + minor * std::cos(b)) * std::cos(a), minor * std::sin(b), (major + minor * std::cos(b)) * std::sin(a));
      // Tilted about the x axis so the hole is seen at an angle.
      o.vertices.push_back(centre + Vec3(p.x, std::cos(tilt) * p.y - std::sin(tilt) * p.z, std::sin(tilt) * p.y + std::cos(tilt) * p.z));
    }
  auto at = [&](int i, int j) { return (i % rings) * sides + (j % sides); };
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < sides; ++j) {
      o.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      o.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return o;
}

// An open bowl: the lower half of a bumpy sphere (its rim is open), its inside facing up
// (single-sided faces: the inside is what faces a ceiling light and blocks it).
inline Object bowl(const std::string& id, Vec3 centre, double radius, int stacks, double bump, uint64_t seed) {
  Object sphere = bumpySphere(id, centre, radius, stacks, bump, seed);
  Object o = sphere;
  o.faces.clear();
  for (const auto& f : sphere.faces) {
    bool lower = true;
    for (int k : f) lower = lower && sphere.vertices[size_t(k)].y <= centre.y + 1e-12;
    if (lower) o.faces.push_back({f.rbegin(), f.rend()});
  }
  return o;
}

// Reverses a seeded fraction of the faces (an inconsistently oriented mesh).
inline Object withFlips(Object o, double fraction, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::bernoulli_distribution flip(fraction);
  for (auto& f : o.faces)
    if (flip(rng)) std::reverse(f.begin(), f.end());
  return o;
}

// A square light of half-side `half` at height 3, facing down onto the meshes below.
inline Light ceilingLight(double half) {
  Light light;
  light.id = "light";
  light.polygon = {{-half, 3, -half}, {half, 3, -half}, {half, 3, half}, {-half, 3, half}};
  light.radiance = Vec3(10);
  return light;
}

// The chain tests' seeded meshes, floating 0.5–1.9 m over the floor under ceilingLight():
// closed non-convex, closed of genus 1, open, and inconsistently oriented.
struct NamedMesh {
  const char* name;
  Object mesh;
};
inline std::vector<NamedMesh> seededMeshes(uint64_t seed) {
  return {
      {"bumpy sphere", bumpySphere("m", {0.1, 1.2, -0.05}, 0.5, 10, 0.3, seed)},
      {"torus", torus("m", {0.0, 1.3, 0.1}, 0.45, 0.15, 24, 10, 0.5 + 0.1 * double(seed % 5))},
      {"open bowl", bowl("m", {0.0, 1.4, 0.0}, 0.5, 12, 0.2, seed)},
      {"flipped faces", withFlips(bumpySphere("m", {0.0, 1.2, 0.0}, 0.45, 8, 0.25, seed), 0.2, seed)},
  };
}

}  // namespace penumbra::test
