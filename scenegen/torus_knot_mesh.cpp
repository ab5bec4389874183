#include "scenegen/torus_knot_mesh.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {

const double kPi = std::acos(-1.0);

Vec3 centreLine(int p, int q, double t) {
  const double r = 2 + std::cos(q * t);
  return Vec3(r * std::cos(p * t), -std::sin(q * t), r * std::sin(p * t));
}

Vec3 tangent(int p, int q, double t) {
  const double r = 2 + std::cos(q * t), dr = -q * std::sin(q * t);
  return glm::normalize(Vec3(dr * std::cos(p * t) - r * p * std::sin(p * t), -q * std::cos(q * t),
                             dr * std::sin(p * t) + r * p * std::cos(p * t)));
}

}  // namespace

TriMesh torusKnotMesh(const TorusKnotOptions& options) {
  const int p = options.p, q = options.q;
  if (p < 1 || q < 1) throw std::invalid_argument("torusKnotMesh: p and q must be >= 1");
  if (!(options.tubeRadius > 0 && options.tubeRadius <= 0.5))
    throw std::invalid_argument("torusKnotMesh: tube radius must be in (0, 0.5]");
  if (options.triangles < 24)
    throw std::invalid_argument("torusKnotMesh: needs at least 24 triangles");
  // Length of the centre line, for about square cells.
  double length = 0;
  for (int k = 0; k < 4096; ++k)
    length += glm::length(centreLine(p, q, 2 * kPi * (k + 1) / 4096) -
                          centreLine(p, q, 2 * kPi * k / 4096));
  const double aspect = length / (2 * kPi * options.tubeRadius);  // segments per side
  const int sides = std::max(3, int(std::lround(std::sqrt(options.triangles / (2 * aspect)))));
  const int segments = std::max(4, int(std::lround(options.triangles / (2.0 * sides))));

  TriMesh mesh;
  for (int i = 0; i < segments; ++i) {
    const double t = 2 * kPi * i / segments;
    const Vec3 c = centreLine(p, q, t), tan = tangent(p, q, t);
    // From the torus's core circle (radius 2 in the xz plane) to the line: never along c′.
    const Vec3 core = 2.0 * Vec3(std::cos(p * t), 0, std::sin(p * t));
    const Vec3 offset = c - core;
    const Vec3 n = glm::normalize(offset - glm::dot(offset, tan) * tan);
    const Vec3 b = glm::cross(tan, n);
    for (int j = 0; j < sides; ++j) {
      const double a = 2 * kPi * j / sides;
      mesh.vertices.push_back(c + options.tubeRadius * (std::cos(a) * n + std::sin(a) * b));
    }
  }
  auto at = [&](int i, int j) { return (i % segments) * sides + (j % sides); };
  // Ring i to ring i + 1 along c′, j round it from n to b = c′ × n: (∂/∂a × ∂/∂t) points out.
  for (int i = 0; i < segments; ++i)
    for (int j = 0; j < sides; ++j) {
      mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return weldedMesh(mesh.vertices, mesh.triangles);
}

}  // namespace penumbra
