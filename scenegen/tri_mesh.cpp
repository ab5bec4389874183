#include "scenegen/tri_mesh.h"

#include <algorithm>
#include <limits>
#include <map>
#include <stdexcept>
#include <tuple>

namespace penumbra {

TriMesh weldedMesh(const std::vector<Vec3>& positions,
                   const std::vector<std::array<int, 3>>& triangles) {
  // Ordered by (x, y, z) with ==: −0 and +0 are one position.
  std::map<std::tuple<double, double, double>, int> index;
  std::vector<int> remap(positions.size(), -1);
  TriMesh out;
  auto vertex = [&](int i) {
    if (remap[size_t(i)] >= 0) return remap[size_t(i)];
    const Vec3& p = positions[size_t(i)];
    const auto [it, inserted] =
        index.emplace(std::make_tuple(p.x, p.y, p.z), int(out.vertices.size()));
    if (inserted) out.vertices.push_back(p);
    return remap[size_t(i)] = it->second;
  };
  out.triangles.reserve(triangles.size());
  for (const auto& t : triangles) {
    for (int i : t)
      if (i < 0 || size_t(i) >= positions.size())
        throw std::out_of_range("weldedMesh: index out of range");
    const std::array<int, 3> w{vertex(t[0]), vertex(t[1]), vertex(t[2])};
    if (w[0] != w[1] && w[1] != w[2] && w[2] != w[0]) out.triangles.push_back(w);
  }
  return out;
}

MeshEdges meshEdges(const TriMesh& mesh) {
  std::map<std::pair<int, int>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) ++directed[{t[size_t(k)], t[size_t((k + 1) % 3)]}];
  MeshEdges out;
  for (const auto& [edge, uses] : directed) {
    if (uses > 1) ++out.repeated;
    const auto reverse = directed.find({edge.second, edge.first});
    const int back = reverse == directed.end() ? 0 : reverse->second;
    // Count each undirected edge once: from its lower-first direction, or from the only one.
    if (back > 0 && edge.first > edge.second) continue;
    ++out.edges;
    if (uses + back == 1) ++out.boundary;
    if (uses + back > 2) ++out.overShared;
  }
  return out;
}

double signedVolume(const TriMesh& mesh) {
  double sum = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[size_t(t[0])];
    const Vec3& b = mesh.vertices[size_t(t[1])];
    const Vec3& c = mesh.vertices[size_t(t[2])];
    sum += glm::dot(a, glm::cross(b, c));
  }
  return sum / 6;
}

void flipTriangles(TriMesh& mesh) {
  for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
}

MeshBounds meshBounds(const TriMesh& mesh) {
  MeshBounds b;
  if (mesh.vertices.empty()) return b;
  b.min = b.max = mesh.vertices.front();
  for (const Vec3& v : mesh.vertices) {
    b.min = glm::min(b.min, v);
    b.max = glm::max(b.max, v);
  }
  return b;
}

TriMesh placedMesh(const TriMesh& mesh, double scale, const Vec3& at, bool rest) {
  if (mesh.vertices.empty() || !(scale > 0))
    throw std::invalid_argument("placedMesh: empty mesh or scale <= 0");
  const Vec3 c = meshBounds(mesh).centre();
  std::vector<Vec3> positions;
  positions.reserve(mesh.vertices.size());
  double lowest = std::numeric_limits<double>::infinity();
  for (const Vec3& v : mesh.vertices) {
    positions.push_back(Vec3(at.x, rest ? 0.0 : at.y, at.z) + scale * (v - c));
    lowest = std::min(lowest, positions.back().y);
  }
  if (rest)
    for (Vec3& p : positions) p.y = (p.y - lowest) + at.y;  // the lowest: exactly at.y
  return weldedMesh(positions, mesh.triangles);
}

TriMesh objectMesh(const Object& object) {
  TriMesh mesh;
  mesh.vertices = object.vertices;
  for (const auto& face : object.faces)
    for (size_t k = 1; k + 1 < face.size(); ++k)
      mesh.triangles.push_back({face[0], face[k], face[k + 1]});
  return mesh;
}

Object meshObject(const std::string& id, const TriMesh& mesh, const std::string& material) {
  Object object;
  object.id = id;
  object.material = material;
  object.vertices = mesh.vertices;
  object.faces.reserve(mesh.triangles.size());
  for (const auto& t : mesh.triangles) object.faces.push_back({t[0], t[1], t[2]});
  return object;
}

}  // namespace penumbra
