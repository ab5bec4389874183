#include "core/scene/closed_convex.h"

#include <algorithm>
#include <tuple>
#include <utility>

namespace penumbra {

namespace {

bool lexLess(const Vec3& a, const Vec3& b) {
  return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
}

// Per vertex index, the smallest index at the same object-space position: imported
// meshes often repeat a corner per face (split normals or texture seams).
std::vector<int> weldedIndices(const std::vector<Vec3>& vertices) {
  std::vector<int> order(vertices.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = int(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return lexLess(vertices[size_t(a)], vertices[size_t(b)]); });
  std::vector<int> canonical(vertices.size());
  for (size_t i = 0; i < order.size(); ++i) {
    const bool sameAsPrevious =
        i > 0 && vertices[size_t(order[i])] == vertices[size_t(order[i - 1])];
    canonical[size_t(order[i])] = sameAsPrevious ? canonical[size_t(order[i - 1])] : order[i];
  }
  return canonical;
}

}  // namespace

bool isClosedOriented(const Object& object) {
  if (object.faces.empty()) return false;
  const std::vector<int> welded = weldedIndices(object.vertices);
  std::vector<std::pair<int, int>> edges;  // directed, as the faces traverse them
  for (const auto& face : object.faces)
    for (size_t i = 0; i < face.size(); ++i) {
      const int a = welded[size_t(face[i])], b = welded[size_t(face[(i + 1) % face.size()])];
      if (a != b) edges.push_back({a, b});
    }
  std::sort(edges.begin(), edges.end());
  // Each directed edge once (two faces traversing it alike are misoriented, three or
  // more faces on one edge are not a surface), and its reverse once.
  if (std::adjacent_find(edges.begin(), edges.end()) != edges.end()) return false;
  return std::all_of(edges.begin(), edges.end(), [&](const std::pair<int, int>& e) {
    return std::binary_search(edges.begin(), edges.end(), std::pair<int, int>{e.second, e.first});
  });
}

bool isConvexWithin(const std::vector<Face>& faces, double eps) {
  std::vector<Vec3> vertices;
  for (const Face& face : faces)
    vertices.insert(vertices.end(), face.polygon.begin(), face.polygon.end());
  std::sort(vertices.begin(), vertices.end(), lexLess);
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return std::all_of(faces.begin(), faces.end(), [&](const Face& face) {
    return std::all_of(vertices.begin(), vertices.end(),
                       [&](const Vec3& v) { return face.plane.signedDistance(v) <= eps; });
  });
}

bool isClosedConvex(const Object& object, const std::vector<Face>& worldFaces,
                    const Tolerance& tolerance) {
  // Faces × vertices bounds the convexity test (a closed mesh has about half as many
  // vertices as faces, or as many for quads).
  if (worldFaces.size() * object.vertices.size() > kConvexCheckBudget) return false;
  return isClosedOriented(object) && isConvexWithin(worldFaces, tolerance.length());
}

}  // namespace penumbra
