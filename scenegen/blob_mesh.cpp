#include "scenegen/blob_mesh.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <unordered_map>

namespace penumbra {

namespace {

constexpr double kIso = 0.5;
constexpr double kEdgeMargin = 0.05;  // edge parameters in [margin, 1 − margin]

struct Ball {
  Vec3 centre;
  double radius;
};

struct Field {
  std::vector<Ball> balls;
  double operator()(const Vec3& p) const {
    double sum = 0;
    for (const Ball& b : balls) {
      const Vec3 d = p - b.centre;
      sum += std::exp(-glm::dot(d, d) / (b.radius * b.radius));
    }
    return sum;
  }
};

// Even when the permutation (a, b, c, d) of 0..3 is even.
bool evenPermutation(const std::array<int, 4>& p) {
  int inversions = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) inversions += p[size_t(i)] > p[size_t(j)];
  return inversions % 2 == 0;
}

// The six Kuhn tetrahedra of the unit cube (corner bit 1: x, 2: y, 4: z), each the path
// 0 → e_a → e_a + e_b → 7 for a permutation (a, b, c) of the axes, listed positively
// oriented (det(v1 − v0, v2 − v0, v3 − v0) > 0).
std::array<std::array<int, 4>, 6> kuhnTetrahedra() {
  std::array<std::array<int, 4>, 6> out{};
  std::array<int, 3> axes{0, 1, 2};
  int k = 0;
  do {
    const int a = 1 << axes[0], b = a | (1 << axes[1]);
    std::array<int, 4> tet{0, a, b, 7};
    auto corner = [](int bits) { return Vec3(bits & 1, (bits >> 1) & 1, (bits >> 2) & 1); };
    const Vec3 v0 = corner(tet[0]);
    if (glm::dot(corner(tet[1]) - v0, glm::cross(corner(tet[2]) - v0, corner(tet[3]) - v0)) < 0)
      std::swap(tet[2], tet[3]);
    out[size_t(k++)] = tet;
  } while (std::next_permutation(axes.begin(), axes.end()));
  return out;
}

double minWidth(const TriMesh& mesh) {
  double best = INFINITY;
  for (const auto& t : mesh.triangles) {
    const Vec3 &a = mesh.vertices[size_t(t[0])], &b = mesh.vertices[size_t(t[1])],
               &c = mesh.vertices[size_t(t[2])];
    const double extent = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    best = std::min(best, glm::length(glm::cross(b - a, c - a)) / extent);
  }
  return best;
}

// Marching tetrahedra on n³ cells of side h from `origin`.
TriMesh march(const Field& field, const Vec3& origin, double h, int n) {
  const int m = n + 1;  // grid points per side
  auto id = [&](int i, int j, int k) {
    return (size_t(k) * size_t(m) + size_t(j)) * size_t(m) + size_t(i);
  };
  std::vector<double> values(size_t(m) * size_t(m) * size_t(m));
  for (int k = 0; k < m; ++k)
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) values[id(i, j, k)] = field(origin + h * Vec3(i, j, k));
  auto position = [&](size_t g) {
    const size_t i = g % size_t(m), j = (g / size_t(m)) % size_t(m),
                 k = g / (size_t(m) * size_t(m));
    return origin + h * Vec3(double(i), double(j), double(k));
  };
  TriMesh mesh;
  std::unordered_map<uint64_t, int> edgePoints;
  // The surface point on grid edge (a, b), made once, from the lower index.
  auto edgePoint = [&](size_t a, size_t b) {
    if (a > b) std::swap(a, b);
    const uint64_t key = uint64_t(a) * uint64_t(values.size()) + uint64_t(b);
    const auto [it, inserted] = edgePoints.emplace(key, int(mesh.vertices.size()));
    if (inserted) {
      const double t =
          std::clamp((kIso - values[a]) / (values[b] - values[a]), kEdgeMargin, 1 - kEdgeMargin);
      const Vec3 pa = position(a), pb = position(b);
      mesh.vertices.push_back(pa + t * (pb - pa));
    }
    return it->second;
  };
  const auto tetrahedra = kuhnTetrahedra();
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        size_t corner[8];
        for (int c = 0; c < 8; ++c)
          corner[c] = id(i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1));
        for (const auto& tet : tetrahedra) {
          size_t g[4];
          int insideCount = 0;
          for (int v = 0; v < 4; ++v) {
            g[v] = corner[tet[size_t(v)]];
            insideCount += values[g[v]] >= kIso;
          }
          if (insideCount == 0 || insideCount == 4) continue;
          // (p0, p1, p2, p3): an even permutation of the tetrahedron's corners, the inside
          // ones first (with three inside: the outside one first).
          const bool oneOut = insideCount == 3;
          auto first = [&](int v) { return (values[g[v]] >= kIso) != oneOut; };
          std::array<int, 4> p{};
          int np = 0;
          for (int v = 0; v < 4; ++v)
            if (first(v)) p[size_t(np++)] = v;
          for (int v = 0; v < 4; ++v)
            if (!first(v)) p[size_t(np++)] = v;
          if (!evenPermutation(p)) std::swap(p[2], p[3]);
          auto at = [&](int x, int y) { return edgePoint(g[p[size_t(x)]], g[p[size_t(y)]]); };
          if (insideCount == 2) {
            // Quad (p0p2, p0p3, p1p3, p1p2) faces away from p0, p1: split on its shorter diagonal.
            const int q[4] = {at(0, 2), at(0, 3), at(1, 3), at(1, 2)};
            const double d02 =
                glm::length(mesh.vertices[size_t(q[0])] - mesh.vertices[size_t(q[2])]);
            const double d13 =
                glm::length(mesh.vertices[size_t(q[1])] - mesh.vertices[size_t(q[3])]);
            if (d02 <= d13) {
              mesh.triangles.push_back({q[0], q[1], q[2]});
              mesh.triangles.push_back({q[0], q[2], q[3]});
            } else {
              mesh.triangles.push_back({q[1], q[2], q[3]});
              mesh.triangles.push_back({q[1], q[3], q[0]});
            }
          } else if (!oneOut) {
            mesh.triangles.push_back(
                {at(0, 1), at(0, 2), at(0, 3)});  // faces away from p0 (inside)
          } else {
            mesh.triangles.push_back({at(0, 1), at(0, 3), at(0, 2)});  // faces towards p0 (outside)
          }
        }
      }
  return mesh;
}

}  // namespace

TriMesh blobMesh(const BlobOptions& options) {
  if (options.triangles < 100)
    throw std::invalid_argument("blobMesh: needs at least 100 triangles");
  if (options.balls < 1 || options.balls > 16)
    throw std::invalid_argument("blobMesh: balls must be in 1..16");
  std::mt19937_64 random(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Field field;
  Vec3 at(0.0);
  for (int b = 0; b < options.balls; ++b) {
    const double radius = 0.3 + 0.2 * unit(random);
    if (b > 0) {  // a step of 0.7 s in a random direction from the last centre
      Vec3 d;
      do d = Vec3(2 * unit(random) - 1, 2 * unit(random) - 1, 2 * unit(random) - 1);
      while (glm::length(d) < 0.1 || glm::length(d) > 1);
      at += 0.7 * radius * glm::normalize(d);
    }
    field.balls.push_back({at, radius});
  }
  // Outside the box the field is below ½: each ball adds < ½ / balls beyond s·√ln(2·balls).
  Vec3 lo(INFINITY), hi(-INFINITY);
  for (const Ball& b : field.balls) {
    const double reach = b.radius * std::sqrt(std::log(2.0 * options.balls)) * 1.05;
    lo = glm::min(lo, b.centre - Vec3(reach));
    hi = glm::max(hi, b.centre + Vec3(reach));
  }
  const double side = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  // A grid of cell side h covering the box with two cells to spare each side, less the shift.
  auto marchOn = [&](double h, const Vec3& shift) {
    return march(field, lo - Vec3(2 * h) - h * shift, h, int(std::ceil(side / h)) + 4);
  };
  // Triangles grow as 1/h²: two steps of h ← h·√(made / wanted) from h = side / 12 ...
  const double wanted = options.triangles;
  double h0 = side / 12;
  for (int step = 0; step < 2; ++step) {
    const double made = double(std::max<size_t>(1, marchOn(h0, Vec3(0.0)).triangles.size()));
    h0 = std::min(side / 4, h0 * std::sqrt(made / wanted));
  }
  // ... then the nearest count among h0 · (1 + 0.04 k), |k| ≤ 3 (≤ 1 from 20,000 on; coarse
  // grids count unevenly), each grid shifted by a seeded part of a cell while a triangle is
  // thinner than 1 % of a cell.
  TriMesh best;
  double bestError = INFINITY;
  bool bestThick = false;
  const int spread = wanted < 20000 ? 3 : 1;
  for (int k = -spread; k <= spread; ++k) {
    const double h = h0 * (1 + 0.04 * k);
    TriMesh mesh = marchOn(h, Vec3(0.0));
    double width = minWidth(mesh);
    for (int attempt = 1; attempt < 8 && width < 0.01 * h; ++attempt) {
      TriMesh shifted = marchOn(h, Vec3(unit(random), unit(random), unit(random)));
      if (const double w = minWidth(shifted); w > width) {
        width = w;
        mesh = std::move(shifted);
      }
    }
    const bool thick = width >= 0.01 * h;
    const double error = std::abs(double(mesh.triangles.size()) - wanted);
    if ((thick && !bestThick) || (thick == bestThick && error < bestError)) {
      best = std::move(mesh);
      bestError = error;
      bestThick = thick;
    }
  }
  return weldedMesh(best.vertices, best.triangles);
}

}  // namespace penumbra
