#include "core/volume/surface_points.h"

#include <algorithm>
#include <array>

namespace penumbra::volume {

namespace {

// The 12 edges of a cell as pairs of corner indices (corner bits: x = 1, y = 2, z = 4).
constexpr std::array<std::array<int, 2>, 12> kEdges{{{0, 1},
                                                     {2, 3},
                                                     {4, 5},
                                                     {6, 7},
                                                     {0, 2},
                                                     {1, 3},
                                                     {4, 6},
                                                     {5, 7},
                                                     {0, 4},
                                                     {1, 5},
                                                     {2, 6},
                                                     {3, 7}}};

}  // namespace

SurfacePoints surfacePoints(const ScalarVolume& data, double isovalue, int maxCellsPerSide) {
  SurfacePoints out;
  const glm::ivec3 size = data.size();
  const int longest = std::max({size.x, size.y, size.z}) - 1;
  out.stride =
      std::max(1, (longest + std::max(1, maxCellsPerSide) - 1) / std::max(1, maxCellsPerSide));
  const int s = out.stride;
  // Sample positions per axis: 0, s, 2s, ..., and the last voxel.
  auto samples = [&](int n) {
    std::vector<int> at;
    for (int i = 0; i < n - 1; i += s) at.push_back(i);
    at.push_back(n - 1);
    return at;
  };
  const std::vector<int> xs = samples(size.x), ys = samples(size.y), zs = samples(size.z);
  std::vector<double> grid(xs.size() * ys.size() * zs.size());
  auto at = [&](size_t i, size_t j, size_t k) -> double& {
    return grid[(k * ys.size() + j) * xs.size() + i];
  };
  for (size_t k = 0; k < zs.size(); ++k)
    for (size_t j = 0; j < ys.size(); ++j)
      for (size_t i = 0; i < xs.size(); ++i) at(i, j, k) = data.voxel({xs[i], ys[j], zs[k]});
  const Mat3& objectFromVoxel = data.objectFromVoxel();
  const Mat3 normalMatrix = glm::transpose(glm::inverse(objectFromVoxel));
  for (size_t k = 0; k + 1 < zs.size(); ++k)
    for (size_t j = 0; j + 1 < ys.size(); ++j)
      for (size_t i = 0; i + 1 < xs.size(); ++i) {
        std::array<double, 8> f;
        std::array<Vec3, 8> p;
        for (int c = 0; c < 8; ++c) {
          const size_t ci = i + (c & 1), cj = j + ((c >> 1) & 1), ck = k + ((c >> 2) & 1);
          f[c] = at(ci, cj, ck) - isovalue;
          p[c] = Vec3(xs[ci], ys[cj], zs[ck]);
        }
        Vec3 sum(0.0);
        int crossings = 0;
        for (const auto& [a, b] : kEdges) {
          if ((f[a] > 0) == (f[b] > 0)) continue;
          const double t = f[a] / (f[a] - f[b]);
          sum += p[a] + t * (p[b] - p[a]);
          ++crossings;
        }
        if (crossings == 0) continue;
        // The gradient of the cell's trilinear field at its centre: mean differences per axis.
        Vec3 gradient(0.0);
        for (int c = 0; c < 8; ++c)
          for (int axis = 0; axis < 3; ++axis)
            gradient[axis] += ((c >> axis) & 1 ? 0.25 : -0.25) * f[c];
        Vec3 normal = normalMatrix * (gradient / (p[7] - p[0]));
        const double length = glm::length(normal);
        out.points.push_back(objectFromVoxel * (sum / double(crossings)));
        out.normals.push_back(length > 0 ? normal / length : Vec3(0.0));
      }
  return out;
}

}  // namespace penumbra::volume
