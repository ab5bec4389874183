#include "scenegen/scan_mesh.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>

namespace penumbra {

namespace {

// The 12 corners and 20 outward faces of the icosahedron.
void icosahedron(std::vector<Vec3>& corners, std::vector<std::array<int, 3>>& faces) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  corners = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
             {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  faces = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
           {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
           {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
}

}  // namespace

TriMesh scanMesh(const ScanOptions& options) {
  if (options.triangles < 20) throw std::invalid_argument("scanMesh: needs at least 20 triangles");
  const int f = std::max(1, int(std::lround(std::sqrt(options.triangles / 20.0))));
  std::vector<Vec3> corners;
  std::vector<std::array<int, 3>> faces;
  icosahedron(corners, faces);

  // A lattice point is Σ wᵢ·cornerᵢ / f over its (corner, weight) pairs with w > 0, summed
  // in corner order: the faces sharing an edge or corner compute it alike.
  std::map<std::vector<std::pair<int, int>>, int> index;
  TriMesh mesh;
  auto point = [&](const std::array<int, 3>& face, int a, int b) {
    std::vector<std::pair<int, int>> key;
    const int weights[3] = {f - a - b, a, b};
    for (int k = 0; k < 3; ++k)
      if (weights[k] > 0) key.push_back({face[size_t(k)], weights[k]});
    std::sort(key.begin(), key.end());
    const auto [it, inserted] = index.emplace(key, int(mesh.vertices.size()));
    if (inserted) {
      Vec3 p(0.0);
      for (const auto& [corner, w] : key) p += double(w) * corners[size_t(corner)];
      mesh.vertices.push_back(glm::normalize(p));
    }
    return it->second;
  };
  for (const auto& face : faces)
    for (int a = 0; a < f; ++a)
      for (int b = 0; a + b < f; ++b) {
        // Corners (a, b), (a + 1, b), (a, b + 1) in the face's own counter-clockwise order.
        mesh.triangles.push_back({point(face, a, b), point(face, a + 1, b), point(face, a, b + 1)});
        if (a + b + 1 < f)
          mesh.triangles.push_back(
              {point(face, a + 1, b), point(face, a + 1, b + 1), point(face, a, b + 1)});
      }

  // Seeded lumps and dents, then the per-vertex jitter, both along the vertex's direction.
  std::mt19937_64 random(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  struct Bump {
    Vec3 direction;
    double height, width;
  };
  std::vector<Bump> bumps;
  for (int k = 0; k < 12; ++k) {
    Vec3 d;
    do d = Vec3(unit(random), unit(random), unit(random));
    while (glm::length(d) < 0.1 || glm::length(d) > 1);
    bumps.push_back({glm::normalize(d), 0.12 * unit(random), 0.15 + 0.25 * (unit(random) + 1) / 2});
  }
  for (Vec3& u : mesh.vertices) {
    double r = 1;
    for (const Bump& bump : bumps) {
      const double angle = std::acos(std::clamp(glm::dot(u, bump.direction), -1.0, 1.0));
      r += bump.height * std::exp(-(angle * angle) / (bump.width * bump.width));
    }
    r *= 1 + 0.004 * unit(random);
    u *= r;
  }
  return weldedMesh(mesh.vertices, mesh.triangles);
}

}  // namespace penumbra
