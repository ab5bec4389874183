#include "scenegen/bowl_mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

TriMesh bowlMesh(int triangles) {
  if (triangles < 24) throw std::invalid_argument("bowlMesh: needs at least 24 triangles");
  const double pi = std::acos(-1.0);
  // slices · (2 · stacks − 1) ≈ 4 · stacks² with slices = 2 · stacks.
  const int stacks = std::max(2, int(std::lround(std::sqrt(triangles / 4.0))));
  const int slices = std::max(3, int(std::lround(double(triangles) / (2 * stacks - 1))));
  TriMesh mesh;
  mesh.vertices.push_back(Vec3(0, -1, 0));  // the pole
  for (int ring = 1; ring <= stacks; ++ring) {
    const double polar = 0.5 * pi * ring / stacks;  // from the pole; the rim at π/2
    const double y = ring == stacks ? 0.0 : -std::cos(polar);
    for (int j = 0; j < slices; ++j) {
      const double a = 2 * pi * j / slices;
      mesh.vertices.push_back(
          Vec3(std::sin(polar) * std::cos(a), y, std::sin(polar) * std::sin(a)));
    }
  }
  auto at = [&](int ring, int j) { return 1 + (ring - 1) * slices + (j % slices); };
  // Counter-clockwise seen from the centre (above the bowl): x → z turns clockwise seen
  // from above, so each triangle goes j + 1 → j.
  for (int j = 0; j < slices; ++j) mesh.triangles.push_back({0, at(1, j + 1), at(1, j)});
  for (int ring = 1; ring < stacks; ++ring)
    for (int j = 0; j < slices; ++j) {
      mesh.triangles.push_back({at(ring, j), at(ring, j + 1), at(ring + 1, j + 1)});
      mesh.triangles.push_back({at(ring, j), at(ring + 1, j + 1), at(ring + 1, j)});
    }
  return weldedMesh(mesh.vertices, mesh.triangles);
}

}  // namespace penumbra
