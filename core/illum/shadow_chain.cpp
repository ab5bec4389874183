#include "core/illum/shadow_chain.h"

#include "core/util/stamped_set.h"

#include <algorithm>
#include <cstdlib>

namespace penumbra {

bool appendShadowChain(const MeshTopology& mesh, std::span<const uint32_t> chainFaces,
                       std::span<const uint32_t> chainClusters,
                       std::span<const std::pair<uint32_t, int>> summedEdges, const Vec3& p,
                       const Plane& lightPlane, double pHeight, const PlaneFrame& frame, double minArea,
                       std::vector<ChainEdge>& out) {
  const ConvexSolid& w = mesh.welded;
  // Kept between calls: net all 0 (each touched edge is reset below), each corner projected
  // once per call (a round of the memo): no per-call pass over the whole mesh.
  thread_local std::vector<int> net;
  thread_local std::vector<uint32_t> touched;
  thread_local StampedMemo<Vec2> projected;
  if (net.size() < w.edges.size()) net.resize(w.edges.size(), 0);
  projected.clear(w.vertices.size());
  touched.clear();
  for (const auto& [e, count] : summedEdges) {
    if (net[e] == 0) touched.push_back(e);
    net[e] += count;
  }
  for (const uint32_t c : chainClusters) {  // a whole cluster: its sum, inner edges cancelled
    for (uint32_t i = mesh.clusterChainStarts[c]; i < mesh.clusterChainStarts[c + 1]; ++i) {
      const auto [e, count] = mesh.clusterChain[i];
      if (net[e] == 0) touched.push_back(e);
      net[e] += count;
    }
  }
  for (const uint32_t f : chainFaces) addFaceEdges(mesh, f, net, touched);
  auto project = [&](uint32_t v) -> const Vec2& {
    return projected.value(v, [&](uint32_t) {
      const Vec3& x = w.vertices[v];
      return frame.to2D(p + (x - p) * (pHeight / (pHeight - lightPlane.signedDistance(x))));
    });
  };
  const size_t first = out.size();
  double area2 = 0;  // twice the signed area of the projected blocking faces, summed
  for (uint32_t e : touched) {
    const int count = net[e];
    net[e] = 0;  // an edge may be touched twice (its balance passed through 0)
    if (count == 0) continue;
    const Vec2 &a = project(w.edges[e].first), &b = project(w.edges[e].second);
    ChainEdge edge = count > 0 ? ChainEdge{a, b, count} : ChainEdge{b, a, -count};
    area2 += edge.count * cross2(edge.from, edge.to);
    out.push_back(edge);
  }
  if (!(std::abs(area2) > 2 * minArea)) {
    out.resize(first);
    return false;
  }
  if (area2 < 0)
    for (size_t i = first; i < out.size(); ++i) std::swap(out[i].from, out[i].to);
  return true;
}

void mergeChainEdges(std::vector<ChainEdge>& chain) {
  auto less = [](const Vec2& a, const Vec2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); };
  for (ChainEdge& e : chain)  // canonical direction: from the lesser end, count signed
    if (less(e.to, e.from)) std::swap(e.from, e.to), e.count = -e.count;
  std::sort(chain.begin(), chain.end(), [&](const ChainEdge& x, const ChainEdge& y) {
    return less(x.from, y.from) || (x.from == y.from && less(x.to, y.to));
  });
  size_t kept = 0;
  for (size_t i = 0; i < chain.size();) {
    ChainEdge sum = chain[i];
    size_t j = i + 1;
    for (; j < chain.size() && chain[j].from == sum.from && chain[j].to == sum.to; ++j) sum.count += chain[j].count;
    if (sum.count < 0) std::swap(sum.from, sum.to), sum.count = -sum.count;
    if (sum.count != 0) chain[kept++] = sum;
    i = j;
  }
  chain.resize(kept);
}

int chainWinding(std::span<const ChainEdge> chain, const Vec2& x, const Vec2& ray, size_t skip) {
  int w = 0;
  // In coordinates with the ray along +x: (along, across).
  auto local = [&](const Vec2& q) { return Vec2(glm::dot(q - x, ray), cross2(ray, q - x)); };
  for (size_t i = 0; i < chain.size(); ++i) {
    if (i == skip) continue;
    const Vec2 a = local(chain[i].from), b = local(chain[i].to);
    if (a.y <= 0) {
      if (b.y > 0 && cross2(a, b) > 0) w += chain[i].count;
    } else if (b.y <= 0 && cross2(a, b) < 0) {
      w -= chain[i].count;
    }
  }
  return w;
}

}  // namespace penumbra
