#include "core/mesh/cell_triangulation.h"

namespace penumbra {

CellTriangulation triangulateConvexCell(const Polygon2& loop, double eps) {
  CellTriangulation out;
  const uint32_t n = uint32_t(loop.size());
  if (n < 3) return out;
  // A vertex is a corner if it is not (within eps) on the segment of its neighbours.
  std::vector<bool> corner(n);
  for (uint32_t i = 0; i < n; ++i)
    corner[i] = lineDistance(loop[(i + n - 1) % n], loop[(i + 1) % n], loop[i]) < -eps ||
                lineDistance(loop[(i + n - 1) % n], loop[(i + 1) % n], loop[i]) > eps;
  // A fan apex must be a corner whose both neighbours are corners too: then no
  // fan triangle has its three vertices on one side.
  for (uint32_t apex = 0; apex < n; ++apex) {
    if (!corner[apex] || !corner[(apex + 1) % n] || !corner[(apex + n - 1) % n]) continue;
    for (uint32_t k = 1; k + 1 < n; ++k)
      out.triangles.push_back({apex, (apex + k) % n, (apex + k + 1) % n});
    return out;
  }
  out.usesCentre = true;
  for (uint32_t i = 0; i < n; ++i) out.triangles.push_back({n, i, (i + 1) % n});
  return out;
}

}  // namespace penumbra
