#include "interchange/mesh_orientation.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <numeric>
#include <unordered_map>

namespace penumbra::interchange {

namespace {

// One face's use of an undirected edge: `forward` when the face runs from the smaller index.
struct EdgeUse {
  size_t face;
  bool forward;
};

using EdgeMap = std::unordered_map<uint64_t, std::vector<EdgeUse>>;

uint64_t edgeKey(int a, int b) {
  const auto lo = uint32_t(std::min(a, b)), hi = uint32_t(std::max(a, b));
  return (uint64_t(lo) << 32) | hi;
}

EdgeMap edgesOf(const std::vector<IndexPolygon>& faces) {
  EdgeMap edges;
  for (size_t f = 0; f < faces.size(); ++f) {
    const IndexPolygon& face = faces[f];
    for (size_t k = 0; k < face.size(); ++k) {
      const int a = face[k], b = face[(k + 1) % face.size()];
      if (a != b) edges[edgeKey(a, b)].push_back({f, a < b});
    }
  }
  return edges;
}

// The two faces of an edge of exactly two distinct faces; nullptr otherwise.
const std::vector<EdgeUse>* manifoldPair(const std::vector<EdgeUse>& uses) {
  return uses.size() == 2 && uses[0].face != uses[1].face ? &uses : nullptr;
}

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), size_t(0));
  }
  size_t find(size_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void join(size_t a, size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<size_t> parent_;
};

// Faces grouped by component (neighbours across manifold edges), components in order of first face.
std::vector<std::vector<size_t>> componentsOf(size_t faceCount, const EdgeMap& edges) {
  UnionFind sets(faceCount);
  for (const auto& [key, uses] : edges)
    if (manifoldPair(uses)) sets.join(uses[0].face, uses[1].face);
  std::vector<std::vector<size_t>> components;
  std::unordered_map<size_t, size_t> indexOfRoot;
  for (size_t f = 0; f < faceCount; ++f) {
    const auto [it, fresh] = indexOfRoot.emplace(sets.find(f), components.size());
    if (fresh) components.emplace_back();
    components[it->second].push_back(f);
  }
  return components;
}

// Faces with an edge that is not closed: not shared by exactly two faces running opposite ways
// (`flipped[f]`: face f is read reversed).
std::vector<bool> facesOnOpenEdges(size_t faceCount, const EdgeMap& edges,
                                   const std::vector<bool>& flipped) {
  std::vector<bool> open(faceCount, false);
  for (const auto& [key, uses] : edges) {
    const bool closedEdge = manifoldPair(uses) && (uses[0].forward != flipped[uses[0].face]) !=
                                                      (uses[1].forward != flipped[uses[1].face]);
    if (!closedEdge)
      for (const EdgeUse& use : uses) open[use.face] = true;
  }
  return open;
}

bool isClosed(const std::vector<size_t>& component, const std::vector<bool>& faceOnOpenEdge) {
  return std::none_of(component.begin(), component.end(),
                      [&](size_t f) { return faceOnOpenEdge[f]; });
}

// Counts components, closed ones and edge kinds, faces read reversed where flipped.
SurfaceFacts factsOf(size_t faceCount, const EdgeMap& edges,
                     const std::vector<std::vector<size_t>>& components,
                     const std::vector<bool>& flipped) {
  SurfaceFacts facts;
  facts.components = components.size();
  for (const auto& [key, uses] : edges) {
    if (uses.size() >= 3) ++facts.nonManifoldEdges;
    if (uses.size() == 1) ++facts.boundaryEdges;
  }
  const std::vector<bool> open = facesOnOpenEdges(faceCount, edges, flipped);
  for (const std::vector<size_t>& component : components)
    if (isClosed(component, open)) ++facts.closedComponents;
  return facts;
}

// Six times the signed volume bounded by the faces (fan triangles), read reversed where flipped.
double sixVolume(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces,
                 const std::vector<size_t>& component, const std::vector<bool>& flipped,
                 const Vec3& origin) {
  double sum = 0;
  for (size_t f : component) {
    const IndexPolygon& face = faces[f];
    const Vec3 a = positions[size_t(face[0])] - origin;
    for (size_t k = 1; k + 1 < face.size(); ++k) {
      const Vec3 b = positions[size_t(face[k])] - origin,
                 c = positions[size_t(face[k + 1])] - origin;
      const double term = glm::dot(a, glm::cross(b, c));
      sum += flipped[f] ? -term : term;
    }
  }
  return sum;
}

// Solid angle of triangle (a, b, c) seen from the origin, signed by its winding
// (Van Oosterom & Strackee 1983).
double solidAngle(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double numerator = glm::dot(a, glm::cross(b, c));
  const double denominator =
      la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  return 2 * std::atan2(numerator, denominator);
}

}  // namespace

double windingNumber(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces,
                     const Vec3& point) {
  double sum = 0;
  for (const IndexPolygon& face : faces) {
    const Vec3 a = positions[size_t(face[0])] - point;
    for (size_t k = 1; k + 1 < face.size(); ++k)
      sum +=
          solidAngle(a, positions[size_t(face[k])] - point, positions[size_t(face[k + 1])] - point);
  }
  return sum / (4 * std::acos(-1.0));
}

SurfaceFacts surfaceFacts(const std::vector<IndexPolygon>& faces) {
  const EdgeMap edges = edgesOf(faces);
  return factsOf(faces.size(), edges, componentsOf(faces.size(), edges),
                 std::vector<bool>(faces.size(), false));
}

SurfaceFacts orientFaces(const std::vector<Vec3>& positions, std::vector<IndexPolygon>& faces,
                         const std::vector<Vec3>& insidePoints) {
  const EdgeMap edges = edgesOf(faces);
  const std::vector<std::vector<size_t>> components = componentsOf(faces.size(), edges);
  // Each face's neighbours across manifold edges, with whether the two run the same way there
  // (then exactly one of them must be flipped).
  std::vector<std::vector<std::pair<size_t, bool>>> neighbours(faces.size());
  for (const auto& [key, uses] : edges)
    if (manifoldPair(uses)) {
      const bool sameWay = uses[0].forward == uses[1].forward;
      neighbours[uses[0].face].push_back({uses[1].face, sameWay});
      neighbours[uses[1].face].push_back({uses[0].face, sameWay});
    }
  // Sorted so that the walk, and so which face of a tie stays, does not depend on hashing.
  for (auto& list : neighbours) std::sort(list.begin(), list.end());

  std::vector<bool> flipped(faces.size(), false), seen(faces.size(), false);
  size_t nonOrientable = 0, turnedOutward = 0, aroundLights = 0;
  for (const std::vector<size_t>& component : components) {
    // Breadth-first from the component's first face, which keeps its winding for now.
    bool orientable = true;
    std::deque<size_t> queue{component.front()};
    seen[component.front()] = true;
    while (!queue.empty()) {
      const size_t f = queue.front();
      queue.pop_front();
      for (const auto& [g, sameWay] : neighbours[f]) {
        const bool wanted = flipped[f] != sameWay;
        if (!seen[g]) {
          seen[g] = true;
          flipped[g] = wanted;
          queue.push_back(g);
        } else if (flipped[g] != wanted) {
          orientable = false;  // a Möbius-like loop: some shared edge stays one way
        }
      }
    }
    if (!orientable) ++nonOrientable;
    // Fewer flips: the majority's winding is taken as the author's.
    const size_t flips = size_t(
        std::count_if(component.begin(), component.end(), [&](size_t f) { return flipped[f]; }));
    if (2 * flips > component.size())
      for (size_t f : component) flipped[f] = !flipped[f];
  }

  // Closed components: outward, or inward around a light.
  const std::vector<bool> open = facesOnOpenEdges(faces.size(), edges, flipped);
  for (const std::vector<size_t>& component : components) {
    if (!isClosed(component, open)) continue;
    // Volume about the component's first corner, so far-off models keep their digits.
    const Vec3 origin = positions[size_t(faces[component.front()][0])];
    Vec3 lo = origin, hi = origin;
    for (size_t f : component)
      for (int i : faces[f]) {
        lo = glm::min(lo, positions[size_t(i)]);
        hi = glm::max(hi, positions[size_t(i)]);
      }
    const double size = glm::length(hi - lo);
    const double volume = sixVolume(positions, faces, component, flipped, origin);
    if (!(std::abs(volume) > 1e-12 * size * size * size)) continue;  // flat: a two-sided sheet
    bool enclosesLight = false;
    if (!insidePoints.empty()) {
      std::vector<IndexPolygon> wound;
      for (size_t f : component) {
        wound.push_back(faces[f]);
        if (flipped[f]) std::reverse(wound.back().begin(), wound.back().end());
      }
      for (const Vec3& point : insidePoints)
        if (std::abs(windingNumber(positions, wound, point)) > 0.5) enclosesLight = true;
    }
    if (enclosesLight) ++aroundLights;
    if ((volume < 0) != enclosesLight) {
      for (size_t f : component) flipped[f] = !flipped[f];
      if (!enclosesLight) ++turnedOutward;
    }
  }

  SurfaceFacts facts = factsOf(faces.size(), edges, components, flipped);
  facts.nonOrientableComponents = nonOrientable;
  facts.closedComponentsTurnedOutward = turnedOutward;
  facts.closedComponentsAroundLights = aroundLights;
  for (size_t f = 0; f < faces.size(); ++f)
    if (flipped[f]) {
      std::reverse(faces[f].begin(), faces[f].end());
      ++facts.facesFlipped;
    }
  return facts;
}

}  // namespace penumbra::interchange
