#include "core/scene/mesh_topology.h"

#include <algorithm>

namespace penumbra {

namespace {

// The six faces of an axis-aligned box, outward and counter-clockwise.
std::vector<Face> boxFaces(const Vec3& low, const Vec3& high) {
  const Vec3 c[8] = {{low.x, low.y, low.z},  {high.x, low.y, low.z},  {high.x, high.y, low.z},  {low.x, high.y, low.z},
                     {low.x, low.y, high.z}, {high.x, low.y, high.z}, {high.x, high.y, high.z}, {low.x, high.y, high.z}};
  const int quads[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {2, 3, 7, 6}, {1, 2, 6, 5}, {0, 4, 7, 3}};
  std::vector<Face> faces;
  for (const auto& q : quads) {
    Face face;
    face.polygon = {c[q[0]], c[q[1]], c[q[2]], c[q[3]]};
    faces.push_back(std::move(face));
  }
  return faces;
}

// CSR lists: for each key in [0, keys), the values paired with it, in pair order.
void groupBy(const std::vector<std::pair<uint32_t, uint32_t>>& pairs, size_t keys, std::vector<uint32_t>& starts,
             std::vector<uint32_t>& values) {
  starts.assign(keys + 1, 0);
  for (const auto& [key, value] : pairs) ++starts[key + 1];
  for (size_t k = 0; k < keys; ++k) starts[k + 1] += starts[k];
  values.assign(pairs.size(), 0);
  std::vector<uint32_t> next(starts.begin(), starts.end() - 1);
  for (const auto& [key, value] : pairs) values[next[key]++] = value;
}

}  // namespace

MeshTopology MeshTopology::of(std::span<const Face> faces, double onPlane, size_t maxElements) {
  MeshTopology mesh;
  mesh.welded = ConvexSolid::of(faces);
  const ConvexSolid& w = mesh.welded;
  if (w.vertices.size() > maxElements || w.edges.size() > maxElements) return mesh;  // too large: not used
  std::vector<std::pair<uint32_t, uint32_t>> edgeUses, vertexUses;
  std::vector<int> balance(w.edges.size(), 0);  // forward minus backward runs
  mesh.cornerEdge.assign(w.corners.size(), kNoEdge);
  mesh.cornerForward.assign(w.corners.size(), 0);
  for (uint32_t f = 0; f + 1 < w.faceStarts.size(); ++f) {
    const uint32_t begin = w.faceStarts[f], end = w.faceStarts[f + 1];
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t a = w.corners[k], b = w.corners[k + 1 < end ? k + 1 : begin];
      vertexUses.push_back({a, f});
      if (a == b) continue;
      const std::pair<uint32_t, uint32_t> key{std::min(a, b), std::max(a, b)};
      const uint32_t e = uint32_t(std::lower_bound(w.edges.begin(), w.edges.end(), key) - w.edges.begin());
      mesh.cornerEdge[k] = e;
      mesh.cornerForward[k] = a < b ? 1 : 0;
      balance[e] += a < b ? 1 : -1;
      edgeUses.push_back({e, f});
    }
  }
  std::sort(vertexUses.begin(), vertexUses.end());
  vertexUses.erase(std::unique(vertexUses.begin(), vertexUses.end()), vertexUses.end());
  groupBy(edgeUses, w.edges.size(), mesh.edgeStarts, mesh.edgeFaces);
  groupBy(vertexUses, w.vertices.size(), mesh.vertexStarts, mesh.vertexFaces);

  mesh.regularEdge.assign(w.edges.size(), 0);
  mesh.regularVertex.assign(w.vertices.size(), 1);
  for (size_t e = 0; e < w.edges.size(); ++e) {
    mesh.regularEdge[e] = mesh.edgeStarts[e + 1] - mesh.edgeStarts[e] == 2 && balance[e] == 0;
    if (!mesh.regularEdge[e]) mesh.regularVertex[w.edges[e].first] = mesh.regularVertex[w.edges[e].second] = 0;
  }

  // faces × corners tests; past 5·10⁷ (as closed_convex.h) every face is taken to have
  // something in front (it only costs a cast that finds nothing).
  mesh.facesSomethingAhead.assign(faces.size(), 1);
  if (double(faces.size()) * double(w.vertices.size()) <= 5e7)
    for (size_t f = 0; f < faces.size(); ++f)
    mesh.facesSomethingAhead[f] = std::any_of(w.vertices.begin(), w.vertices.end(), [&](const Vec3& v) {
      return faces[f].plane.signedDistance(v) > onPlane;
    });

  Vec3 low = w.vertices.empty() ? Vec3(0.0) : w.vertices[0], high = low;
  for (const Vec3& v : w.vertices) {
    low = glm::min(low, v);
    high = glm::max(high, v);
  }
  mesh.box = ConvexSolid::of(boxFaces(low, high));
  return mesh;
}

}  // namespace penumbra
