#include "interchange/corner_normals.h"

#include <cmath>

namespace penumbra::interchange {

namespace {
constexpr double kCosCrease = 0.5;  // 60°
}

std::vector<std::vector<Vec3>> fileNormalsAt(const ImportedGroup& group, const std::vector<int>& remap,
                                             size_t weldedCount) {
  std::vector<std::vector<Vec3>> out;
  if (group.cornerNormals.empty()) return out;
  out.resize(weldedCount);
  for (size_t p = 0; p < group.polygons.size() && p < group.cornerNormals.size(); ++p) {
    const std::vector<Vec3>& normals = group.cornerNormals[p];
    if (normals.size() != group.polygons[p].size()) continue;
    for (size_t k = 0; k < normals.size(); ++k) {
      const double length = glm::length(normals[k]);
      if (!std::isfinite(length) || !(length > 0)) continue;  // a zero or NaN normal says nothing
      out[size_t(remap[size_t(group.polygons[p][k])])].push_back(normals[k] / length);
    }
  }
  return out;
}

nlohmann::json cornerNormalsJson(const std::vector<Vec3>& positions, const std::vector<IndexPolygon>& faces,
                                 const std::vector<std::vector<Vec3>>& normalsAt, size_t& flatCorners) {
  nlohmann::json out = nlohmann::json::array();
  for (const IndexPolygon& face : faces) {
    Vec3 newell(0.0);
    for (size_t k = 0; k < face.size(); ++k)
      newell += glm::cross(positions[size_t(face[k])], positions[size_t(face[(k + 1) % face.size()])]);
    const Vec3 own = glm::length(newell) > 0 ? glm::normalize(newell) : Vec3(0, 0, 1);  // repairs drop degenerates
    nlohmann::json corners = nlohmann::json::array();
    for (int i : face) {
      Vec3 sum(0.0);
      for (const Vec3& n : normalsAt[size_t(i)])
        if (glm::dot(n, own) >= kCosCrease) sum += n;
      const double length = glm::length(sum);
      const Vec3 n = length > 0 ? sum / length : own;
      flatCorners += !(length > 0);
      corners.push_back({n.x, n.y, n.z});
    }
    out.push_back(std::move(corners));
  }
  return out;
}

}  // namespace penumbra::interchange
