#include "core/raycast/mesh_lookup.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace penumbra {

namespace {

// Barycentric coordinates of q may dip this far below 0 and still count as inside (rounding).
constexpr double kInsideSlack = 1e-9;
// Grid size cap per axis: keeps a receiver with a huge triangle count from allocating wildly.
constexpr int kMaxCellsPerAxis = 1024;

// The cell range of a coordinate interval, clamped to the grid.
int cellIndex(double value, double min, double size, int count) {
  const int index = int(std::floor((value - min) / size));
  return std::clamp(index, 0, count - 1);
}

}  // namespace

MeshLookup::Receiver MeshLookup::buildReceiver(const ReceiverMesh& mesh) {
  Receiver receiver;
  receiver.mesh = &mesh;
  const Vec3 anchor = mesh.positions.empty() ? Vec3(0.0) : mesh.positions[0];
  receiver.frame = PlaneFrame::onPlane(Plane::throughPoint(mesh.normal, anchor), anchor);
  receiver.points.reserve(mesh.positions.size());
  Vec2 lo(std::numeric_limits<double>::infinity()), hi(-std::numeric_limits<double>::infinity());
  for (const Vec3& p : mesh.positions) {
    const Vec2 q = receiver.frame.to2D(p);
    receiver.points.push_back(q);
    lo = glm::min(lo, q);
    hi = glm::max(hi, q);
  }
  if (mesh.positions.empty()) lo = hi = Vec2(0.0);
  receiver.min = lo;
  const Vec2 extent = hi - lo;
  const size_t triangles = std::max<size_t>(mesh.triangles.size(), 1);
  // About one triangle per cell on average.
  const double area = std::max(extent.x * extent.y, 1e-300);
  const double side = std::sqrt(area / double(triangles));
  auto count = [&](double length) {
    if (!(side > 0) || !(length > 0)) return 1;
    return std::clamp(int(std::ceil(length / side)), 1, kMaxCellsPerAxis);
  };
  receiver.columns = count(extent.x);
  receiver.rows = count(extent.y);
  const double cellW = extent.x > 0 ? extent.x / receiver.columns : 1.0;
  const double cellH = extent.y > 0 ? extent.y / receiver.rows : 1.0;
  receiver.cellSize = Vec2(cellW, cellH);

  const size_t cells = size_t(receiver.columns) * size_t(receiver.rows);
  std::vector<uint32_t> counts(cells + 1, 0);
  auto forEachCell = [&](const std::array<uint32_t, 3>& t, auto&& visit) {
    Vec2 tlo = receiver.points[t[0]], thi = tlo;
    for (int k = 1; k < 3; ++k) {
      tlo = glm::min(tlo, receiver.points[t[k]]);
      thi = glm::max(thi, receiver.points[t[k]]);
    }
    const int c0 = cellIndex(tlo.x, lo.x, cellW, receiver.columns);
    const int c1 = cellIndex(thi.x, lo.x, cellW, receiver.columns);
    const int r0 = cellIndex(tlo.y, lo.y, cellH, receiver.rows);
    const int r1 = cellIndex(thi.y, lo.y, cellH, receiver.rows);
    for (int r = r0; r <= r1; ++r)
      for (int c = c0; c <= c1; ++c) visit(size_t(r) * receiver.columns + c);
  };
  for (const auto& t : mesh.triangles) forEachCell(t, [&](size_t cell) { ++counts[cell + 1]; });
  for (size_t i = 1; i <= cells; ++i) counts[i] += counts[i - 1];
  receiver.cellStart = counts;
  receiver.cellTriangles.resize(counts[cells]);
  std::vector<uint32_t> fill(counts.begin(), counts.end() - 1);
  for (uint32_t i = 0; i < mesh.triangles.size(); ++i)
    forEachCell(mesh.triangles[i], [&](size_t cell) { receiver.cellTriangles[fill[cell]++] = i; });
  return receiver;
}

MeshLookup::MeshLookup(const Scene& scene, const Mesh& mesh) {
  std::map<FaceId, uint32_t> faceIndex;
  for (uint32_t i = 0; i < scene.faces().size(); ++i) faceIndex[scene.faces()[i].id] = i;
  receiverOfFace_.assign(scene.faces().size(), -1);
  for (const ReceiverMesh& receiverMesh : mesh.receivers) {
    const auto found = faceIndex.find(receiverMesh.face);
    if (found == faceIndex.end() || receiverMesh.positions.empty()) continue;
    // Validated meshes index only their own positions; anything else is skipped, not trusted.
    const bool indicesValid = std::all_of(receiverMesh.triangles.begin(), receiverMesh.triangles.end(),
                                          [&](const auto& t) {
                                            return t[0] < receiverMesh.positions.size() &&
                                                   t[1] < receiverMesh.positions.size() &&
                                                   t[2] < receiverMesh.positions.size();
                                          });
    if (!indicesValid || receiverMesh.irradiance.size() != receiverMesh.positions.size()) continue;
    receiverOfFace_[found->second] = int32_t(receivers_.size());
    receivers_.push_back(buildReceiver(receiverMesh));
  }
}

std::optional<Vec3> MeshLookup::irradiance(uint32_t faceIndex, const Vec3& p) const {
  if (!hasReceiver(faceIndex)) return std::nullopt;
  const Receiver& receiver = receivers_[size_t(receiverOfFace_[faceIndex])];
  return interpolate(receiver, receiver.frame.to2D(p));
}

Vec3 MeshLookup::interpolate(const Receiver& receiver, const Vec2& q) const {
  const ReceiverMesh& mesh = *receiver.mesh;
  if (mesh.triangles.empty()) {
    // No triangles: the value of the nearest vertex.
    size_t best = 0;
    for (size_t i = 1; i < receiver.points.size(); ++i)
      if (glm::length(receiver.points[i] - q) < glm::length(receiver.points[best] - q)) best = i;
    return mesh.irradiance[best];
  }
  const int column = cellIndex(q.x, receiver.min.x, receiver.cellSize.x, receiver.columns);
  const int row = cellIndex(q.y, receiver.min.y, receiver.cellSize.y, receiver.rows);

  // The nearest triangle seen so far: its distance and the value at its closest point.
  double bestDistance = std::numeric_limits<double>::infinity();
  Vec3 bestValue(0.0);
  auto visitTriangle = [&](uint32_t index) -> bool {
    const auto& t = mesh.triangles[index];
    const Vec2 a = receiver.points[t[0]], b = receiver.points[t[1]], c = receiver.points[t[2]];
    const double denominator = cross2(b - a, c - a);
    if (std::abs(denominator) > 0) {
      const double beta = cross2(q - a, c - a) / denominator;
      const double gamma = cross2(b - a, q - a) / denominator;
      const double alpha = 1 - beta - gamma;
      if (alpha >= -kInsideSlack && beta >= -kInsideSlack && gamma >= -kInsideSlack) {
        bestDistance = 0;
        bestValue = alpha * mesh.irradiance[t[0]] + beta * mesh.irradiance[t[1]] +
                    gamma * mesh.irradiance[t[2]];
        return true;
      }
    }
    // Outside (or degenerate): the closest point on its edges.
    for (int e = 0; e < 3; ++e) {
      const uint32_t i0 = t[e], i1 = t[(e + 1) % 3];
      const Vec2 p0 = receiver.points[i0], d = receiver.points[i1] - p0;
      const double length2 = glm::dot(d, d);
      const double s = length2 > 0 ? std::clamp(glm::dot(q - p0, d) / length2, 0.0, 1.0) : 0.0;
      const double distance = glm::length(p0 + s * d - q);
      if (distance < bestDistance) {
        bestDistance = distance;
        bestValue = (1 - s) * mesh.irradiance[i0] + s * mesh.irradiance[i1];
      }
    }
    return false;
  };
  // Rings of cells around q's cell until some triangle has been seen (usually ring 0).
  const int maxRing = std::max(receiver.columns, receiver.rows);
  for (int ring = 0; ring <= maxRing; ++ring) {
    bool sawTriangle = false;
    for (int r = row - ring; r <= row + ring; ++r) {
      if (r < 0 || r >= receiver.rows) continue;
      for (int c = column - ring; c <= column + ring; ++c) {
        if (c < 0 || c >= receiver.columns) continue;
        if (std::max(std::abs(r - row), std::abs(c - column)) != ring) continue;
        const size_t cell = size_t(r) * receiver.columns + c;
        for (uint32_t k = receiver.cellStart[cell]; k < receiver.cellStart[cell + 1]; ++k) {
          sawTriangle = true;
          if (visitTriangle(receiver.cellTriangles[k])) return bestValue;
        }
      }
    }
    if (sawTriangle) break;
  }
  return bestValue;
}

}  // namespace penumbra
