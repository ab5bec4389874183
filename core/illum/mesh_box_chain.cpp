#include "core/illum/mesh_box_chain.h"

#include "core/util/stamped_set.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <span>

namespace penumbra {

namespace {

// |n|·h: how far a plane with normal n moves across a box of half-extent h.
double reach(const Vec3& n, const Vec3& half) {
  return std::abs(n.x) * half.x + std::abs(n.y) * half.y + std::abs(n.z) * half.z;
}

std::array<Vec3, 8> boxCorners(const Vec3& low, const Vec3& high) {
  std::array<Vec3, 8> corners;
  for (int i = 0; i < 8; ++i) corners[i] = Vec3(i & 1 ? high.x : low.x, i & 2 ? high.y : low.y, i & 4 ? high.z : low.z);
  return corners;
}

// A light edge a→b with the sign s that turns m(p) = (b − a) × (p − a) inward for p in
// front of the light: the light's centre is inside, so m(p)·(inner − a) has one sign over the
// front half-space. Found once per box, not once per cluster.
struct LightEdgeSide {
  Vec3 a, edge;
  double s;
};

std::vector<LightEdgeSide> lightEdgeSides(std::span<const Vec3> light, const Plane& lightPlane) {
  std::vector<LightEdgeSide> sides;
  if (light.size() < 3) return sides;
  Vec3 inner{0.0};
  for (const Vec3& v : light) inner += v;
  inner /= double(light.size());
  for (size_t i = 0; i < light.size(); ++i) {
    const Vec3 a = light[i], edge = light[(i + 1) % light.size()] - a;
    const Vec3 front = a + lightPlane.normal;  // a point in front of the light
    sides.push_back({a, edge, glm::dot(glm::cross(edge, front - a), inner - a) < 0 ? -1.0 : 1.0});
  }
  return sides;
}

// Whether the cluster's ball (with a margin) lies outside the cone from every point of the
// box over the light (all of it in front of the light): for some light edge a→b, the plane
// through it and p has the ball on its outer side for every p of the box. The ball is out
// when s·m(p)·(c − a) + r·|m(p)| < 0: linear plus convex in p, so largest at a corner of the
// box, where it is tested.
bool outsideEveryCone(const MeshTopology::Cluster& cluster, const std::array<Vec3, 8>& box,
                      std::span<const LightEdgeSide> sides, double margin) {
  const double r = cluster.radius + margin;
  for (const LightEdgeSide& side : sides) {
    const bool out = std::all_of(box.begin(), box.end(), [&](const Vec3& p) {
      const Vec3 m = glm::cross(side.edge, p - side.a);
      return side.s * glm::dot(m, cluster.centre - side.a) + r * glm::length(m) < 0;
    });
    if (out) return true;
  }
  return false;
}

bool sameBits(const void* a, const void* b, size_t size) { return std::memcmp(a, b, size) == 0; }

struct MemoEntry {
  uint64_t serial = 0;
  std::array<int64_t, 3> cell{};
  int64_t slab = 0;
  Vec3 n{0.0};
  std::vector<Vec3> light;
  Plane lightPlane;
  double sceneSize = 0;
  uint64_t lastUse = 0;
  MeshBoxChain chain;
};

}  // namespace

MeshBoxChain makeMeshBoxChain(const MeshTopology& mesh, const Vec3& low, const Vec3& high, const Vec3& n,
                              std::span<const Vec3> light, const Plane& lightPlane, const Tolerance& tolerance,
                              double highestReceiver) {
  MeshBoxChain out;
  const Vec3 centre = 0.5 * (low + high), half = 0.5 * (high - low);
  const double margin = tolerance.length(), onPlane = tolerance.onPlane();
  // A corner is usable from every point of the box when it lies ahead of the receiver's plane
  // through any point of the box, beyond the light's plane, and below 0.999 of the box's least
  // height over it (the margin a point's own pass asks of each corner: pHeight − h > 1e-3 ·
  // pHeight).
  const double receiverTop = std::min(glm::dot(n, centre) + reach(n, half), highestReceiver);
  const double leastHeight = lightPlane.signedDistance(centre) - reach(lightPlane.normal, half);
  // Corners are judged when a face of a cluster in the cone asks (stamped per call): a box
  // is asked once per receiver plane, and a pass over every corner and edge of a big mesh per
  // receiver of that mesh would make a model's self-casting quadratic.
  thread_local StampedMemo<uint8_t> usableCorner;
  const std::vector<Vec3>& vertices = mesh.welded.vertices;
  usableCorner.clear(vertices.size());
  auto usable = [&](uint32_t v) {
    return usableCorner.value(v, [&](uint32_t) -> uint8_t {
      const double h = lightPlane.signedDistance(vertices[v]);
      return glm::dot(n, vertices[v]) - receiverTop > margin && h > 0 && 0.999 * leastHeight - h > margin;
    }) != 0;
  };
  thread_local std::vector<uint32_t> behindFaces, touched;
  thread_local std::vector<int> net;  // all zero between calls (sumFaceEdges clears what it sets)
  behindFaces.clear();
  if (net.size() < mesh.welded.edges.size()) net.resize(mesh.welded.edges.size(), 0);
  const auto corners = boxCorners(low, high);
  const std::vector<LightEdgeSide> sides = lightEdgeSides(light, lightPlane);
  bool tooMany = false;
  const auto outside = [&](const MeshTopology::Cluster& ball) { return outsideEveryCone(ball, corners, sides, margin); };
  mesh.forEachClusterMeeting(outside, [&](uint32_t c) {
    const MeshTopology::Cluster& cluster = mesh.clusters[c];
    for (uint32_t i = cluster.first; i < cluster.last; ++i) {
      const uint32_t f = mesh.clusterFaces[i];
      bool allUsable = true;
      for (uint32_t k = mesh.welded.faceStarts[f]; k < mesh.welded.faceStarts[f + 1] && allUsable; ++k)
        allUsable = usable(mesh.welded.corners[k]);
      if (!allUsable) {
        // Many faces a point must decide as its own pass does (a receiver on the mesh, or
        // cutting through it): the box saves nothing there.
        if (out.special.size() == mesh.clusterFaces.size() / kMostSpecialShare) {
          tooMany = true;
          return false;
        }
        out.special.push_back(i);
        continue;
      }
      const Plane& plane = mesh.clusterPlanes[i];
      const double middle = plane.signedDistance(centre), spread = reach(plane.normal, half);
      if (middle + spread < -onPlane - margin) behindFaces.push_back(f);
      else if (!(middle - spread > -onPlane + margin)) out.crossing.push_back(i);
    }
    return true;
  });
  if (tooMany) return MeshBoxChain{};
  out.usable = true;
  try {
    sumFaceEdges(mesh, behindFaces, net, touched, out.behindAll);
  } catch (...) {  // an allocation failed midway: the next call on this thread needs net all zero
    std::fill(net.begin(), net.end(), 0);
    throw;
  }
  return out;
}

const MeshBoxChain* meshBoxChain(const MeshTopology& mesh, const Vec3& p, const Vec3& n, std::span<const Vec3> light,
                                 const Plane& lightPlane, const Tolerance& tolerance) {
  const Vec3 low = mesh.box.vertices.empty() ? Vec3(0.0) : mesh.box.vertices.front();
  Vec3 boxLow = low, boxHigh = low;
  for (const Vec3& v : mesh.box.vertices) boxLow = glm::min(boxLow, v), boxHigh = glm::max(boxHigh, v);
  const double side = glm::length(boxHigh - boxLow) / kMeshBoxDivisions;
  if (!(side > 0)) return nullptr;
  std::array<int64_t, 3> cell{};
  for (int a = 0; a < 3; ++a) {
    const double k = std::floor(p[a] / side);
    if (!(std::abs(k) < 0x1p40)) return nullptr;
    cell[a] = int64_t(k);
  }
  // The cell with a length() of room on each side, so that p lies inside it whatever the
  // rounding of floor(p / side).
  const double pad = tolerance.length();
  Vec3 from{0.0}, to{0.0};
  for (int a = 0; a < 3; ++a) {
    from[a] = double(cell[a]) * side - pad;
    to[a] = double(cell[a] + 1) * side + pad;
    if (!(from[a] <= p[a] && p[a] <= to[a])) return nullptr;
  }
  // The points asked lie on a receiver's plane: the box is only the slab of the cube within a
  // few length tolerances of n·p (a step of one, so that the points of one plane share it),
  // flat where n is an axis. A model resting on the floor then has only the corners on the
  // floor unusable from the box, not all those lower than the cube's top.
  const double step = tolerance.length(), k = std::floor(glm::dot(n, p) / step);
  if (!(std::abs(k) < 0x1p50)) return nullptr;
  const double slabLow = k * step - pad, slabHigh = (k + 1) * step + pad;
  if (!(slabLow <= glm::dot(n, p) && glm::dot(n, p) <= slabHigh)) return nullptr;
  for (int a = 0; a < 3; ++a) {
    if (std::abs(n[a]) != 1) continue;
    from[a] = n[a] > 0 ? slabLow : -slabHigh;
    to[a] = n[a] > 0 ? slabHigh : -slabLow;
  }
  const int64_t slab = int64_t(k);
  thread_local std::array<MemoEntry, 16> memo;
  thread_local uint64_t uses = 0;
  MemoEntry* oldest = &memo[0];
  for (MemoEntry& entry : memo) {
    if (entry.serial == mesh.serial && entry.cell == cell && entry.slab == slab && sameBits(&entry.n, &n, sizeof n) &&
        entry.light.size() == light.size() && sameBits(entry.light.data(), light.data(), light.size_bytes()) &&
        sameBits(&entry.lightPlane, &lightPlane, sizeof lightPlane) && entry.sceneSize == tolerance.sceneSize) {
      entry.lastUse = ++uses;
      return &entry.chain;
    }
    if (entry.lastUse < oldest->lastUse) oldest = &entry;
  }
  *oldest = MemoEntry{mesh.serial, cell, slab, n, {light.begin(), light.end()}, lightPlane, tolerance.sceneSize, ++uses,
                      makeMeshBoxChain(mesh, from, to, n, light, lightPlane, tolerance, slabHigh)};
  return &oldest->chain;
}

}  // namespace penumbra
