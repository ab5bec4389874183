#include "bench/lib/mesh_sampling.h"

#include <algorithm>

namespace penumbra {

MeshInterpolator::MeshInterpolator(const Mesh& mesh) : mesh_(mesh) {
  for (size_t i = 0; i < mesh.receivers.size(); ++i) receiverOf_[mesh.receivers[i].face] = i;
}

std::optional<Vec3> MeshInterpolator::at(FaceId face, const Vec3& p) const {
  const auto it = receiverOf_.find(face);
  if (it == receiverOf_.end()) return std::nullopt;
  const ReceiverMesh& r = mesh_.receivers[it->second];
  // The triangle with the largest smallest barycentric weight: robust on shared edges.
  double best = -1;
  Vec3 value{0.0};
  for (const auto& t : r.triangles) {
    const Vec3 a = r.positions[t[0]], b = r.positions[t[1]], c = r.positions[t[2]];
    const double area = glm::dot(glm::cross(b - a, c - a), r.normal);
    if (!(area > 0)) continue;
    const double wa = glm::dot(glm::cross(b - p, c - p), r.normal) / area;
    const double wb = glm::dot(glm::cross(c - p, a - p), r.normal) / area;
    const double wc = 1 - wa - wb;
    const double worst = std::min({wa, wb, wc});
    if (worst > best) {
      best = worst;
      value = wa * r.irradiance[t[0]] + wb * r.irradiance[t[1]] + wc * r.irradiance[t[2]];
    }
    if (worst >= 0) break;
  }
  if (best < -1e-9) return std::nullopt;
  return value;
}

}  // namespace penumbra
