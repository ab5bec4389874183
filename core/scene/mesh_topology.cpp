#include "core/scene/mesh_topology.h"

#include <algorithm>
#include <atomic>
#include <cmath>

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

// Each cluster's faces' edges with their net direction counts (MeshTopology::clusterChain).
void sumClusterChains(MeshTopology& mesh) {
  std::vector<int> net(mesh.welded.edges.size(), 0);
  std::vector<uint32_t> touched;
  mesh.clusterChainStarts.assign(1, 0);
  for (const MeshTopology::Cluster& cluster : mesh.clusters) {
    sumFaceEdges(mesh, std::span(mesh.clusterFaces).subspan(cluster.first, cluster.last - cluster.first), net,
                 touched, mesh.clusterChain);
    mesh.clusterChainStarts.push_back(uint32_t(mesh.clusterChain.size()));
  }
}

// A ball holding balls a and b: around the middle of their box, its radius padded by 1e-7 of
// its size and place so that no rounding in a test of a ball inside it against a plane or a
// box (forEachClusterMeeting) can keep the inner ball while rejecting this one.
MeshTopology::Cluster ballAround(const MeshTopology::Cluster& a, const MeshTopology::Cluster& b) {
  MeshTopology::Cluster ball;
  const Vec3 low = glm::min(a.centre - a.radius, b.centre - b.radius);
  const Vec3 high = glm::max(a.centre + a.radius, b.centre + b.radius);
  ball.centre = 0.5 * (low + high);
  const double radius =
      std::max(glm::length(a.centre - ball.centre) + a.radius, glm::length(b.centre - ball.centre) + b.radius);
  ball.radius = radius + 1e-7 * (radius + glm::length(ball.centre));
  ball.first = a.first;
  ball.last = b.last;
  return ball;
}

// Splits faces order[begin, end) at the median of their centres along the longest side
// of the centres' box until at most kClusterFaces are left, each then a cluster; the splits'
// tree into mesh.clusterTree, in preorder.
void splitIntoClusters(std::vector<uint32_t>& order, size_t begin, size_t end, const std::vector<Vec3>& centres,
                       MeshTopology& mesh) {
  const ConvexSolid& w = mesh.welded;
  const size_t node = mesh.clusterTree.size();
  const uint32_t firstCluster = uint32_t(mesh.clusters.size());
  mesh.clusterTree.emplace_back();
  if (end - begin <= MeshTopology::kClusterFaces) {
    MeshTopology::Cluster cluster;
    cluster.first = uint32_t(begin), cluster.last = uint32_t(end);
    Vec3 low(INFINITY), high(-INFINITY);
    for (size_t i = begin; i < end; ++i)
      for (uint32_t k = w.faceStarts[order[i]]; k < w.faceStarts[order[i] + 1]; ++k) {
        low = glm::min(low, w.vertices[w.corners[k]]);
        high = glm::max(high, w.vertices[w.corners[k]]);
      }
    cluster.centre = 0.5 * (low + high);
    for (size_t i = begin; i < end; ++i)
      for (uint32_t k = w.faceStarts[order[i]]; k < w.faceStarts[order[i] + 1]; ++k)
        cluster.radius = std::max(cluster.radius, glm::length(w.vertices[w.corners[k]] - cluster.centre));
    mesh.clusters.push_back(cluster);
    mesh.clusterTree[node] = {cluster, firstCluster, firstCluster + 1, uint32_t(node + 1)};
    return;
  }
  Vec3 low(INFINITY), high(-INFINITY);
  for (size_t i = begin; i < end; ++i) {
    low = glm::min(low, centres[order[i]]);
    high = glm::max(high, centres[order[i]]);
  }
  const Vec3 side = high - low;
  const int axis = side.x >= side.y && side.x >= side.z ? 0 : side.y >= side.z ? 1 : 2;
  const size_t middle = begin + (end - begin) / 2;
  std::nth_element(order.begin() + long(begin), order.begin() + long(middle), order.begin() + long(end),
                   [&](uint32_t a, uint32_t b) { return centres[a][axis] < centres[b][axis]; });
  splitIntoClusters(order, begin, middle, centres, mesh);
  const size_t right = mesh.clusterTree.size();
  splitIntoClusters(order, middle, end, centres, mesh);
  mesh.clusterTree[node] = {ballAround(mesh.clusterTree[node + 1].ball, mesh.clusterTree[right].ball), firstCluster,
                            uint32_t(mesh.clusters.size()), uint32_t(mesh.clusterTree.size())};
}

}  // namespace

void sumFaceEdges(const MeshTopology& mesh, std::span<const uint32_t> faces, std::vector<int>& net,
                  std::vector<uint32_t>& touched, std::vector<std::pair<uint32_t, int>>& out) {
  touched.clear();
  for (const uint32_t f : faces) addFaceEdges(mesh, f, net, touched);
  for (const uint32_t e : touched) {  // an edge whose balance passed through 0 is listed twice
    if (net[e] != 0) out.push_back({e, net[e]});
    net[e] = 0;
  }
}

MeshTopology MeshTopology::of(std::span<const Face> faces, double onPlane) {
  static std::atomic<uint64_t> made{0};
  MeshTopology mesh;
  mesh.serial = ++made;
  mesh.welded = ConvexSolid::of(faces);
  const ConvexSolid& w = mesh.welded;
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

  std::vector<Vec3> centres(faces.size(), Vec3(0.0));
  for (size_t f = 0; f < faces.size(); ++f) {
    for (uint32_t k = w.faceStarts[f]; k < w.faceStarts[f + 1]; ++k) centres[f] += w.vertices[w.corners[k]];
    centres[f] /= double(std::max<uint32_t>(1, w.faceStarts[f + 1] - w.faceStarts[f]));
  }
  mesh.clusterFaces.resize(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) mesh.clusterFaces[f] = uint32_t(f);
  if (!faces.empty()) splitIntoClusters(mesh.clusterFaces, 0, faces.size(), centres, mesh);
  mesh.faceCluster.assign(faces.size(), 0);
  for (uint32_t c = 0; c < mesh.clusters.size(); ++c)
    for (uint32_t i = mesh.clusters[c].first; i < mesh.clusters[c].last; ++i) mesh.faceCluster[mesh.clusterFaces[i]] = c;
  mesh.clusterPlanes.reserve(faces.size());
  for (uint32_t f : mesh.clusterFaces) mesh.clusterPlanes.push_back(faces[f].plane);
  sumClusterChains(mesh);

  Vec3 low = w.vertices.empty() ? Vec3(0.0) : w.vertices[0], high = low;
  for (const Vec3& v : w.vertices) {
    low = glm::min(low, v);
    high = glm::max(high, v);
  }
  mesh.box = ConvexSolid::of(boxFaces(low, high));
  return mesh;
}

}  // namespace penumbra
