#include "interchange/dm_edges.h"

#include <set>
#include <utility>

namespace penumbra::interchange {

std::vector<Segment3> dmEdges(const Engine& engine) {
  std::vector<Segment3> edges;
  for (const Engine::Receiver& receiver : engine.receivers()) {
    // Each interior edge borders two cells: keep it once (by its sorted ends).
    std::set<std::pair<std::pair<double, double>, std::pair<double, double>>> seen;
    for (const CellId cell : receiver.tree.cells()) {
      const auto polygon = receiver.tree.cellPolygon(cell);
      for (size_t k = 0; k < polygon.size(); ++k) {
        const Vec2 a = polygon[k], b = polygon[(k + 1) % polygon.size()];
        const std::pair<double, double> u{a.x, a.y}, w{b.x, b.y};
        if (!seen.insert(u < w ? std::pair{u, w} : std::pair{w, u}).second) continue;
        edges.push_back({receiver.frame.to3D(a), receiver.frame.to3D(b)});
      }
    }
  }
  return edges;
}

}  // namespace penumbra::interchange
