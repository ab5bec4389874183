#include "core/scene/shading_normal.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace penumbra {

std::optional<std::string> normalsProblem(const std::vector<std::vector<Vec3>>& normals,
                                          const std::vector<std::vector<int>>& faces) {
  if (normals.empty()) return std::nullopt;
  if (normals.size() != faces.size())
    return "has " + std::to_string(normals.size()) + " lists of corner normals for " +
           std::to_string(faces.size()) + " faces";
  for (size_t f = 0; f < faces.size(); ++f) {
    if (normals[f].size() != faces[f].size())
      return "face " + std::to_string(f) + " has " + std::to_string(faces[f].size()) + " corners but " +
             std::to_string(normals[f].size()) + " normals";
    for (const Vec3& n : normals[f]) {
      const double length = glm::length(n);
      if (!std::isfinite(length) || !(length > 1e-12))
        return "face " + std::to_string(f) + " has a corner normal that is not a finite non-zero vector";
    }
  }
  return std::nullopt;
}

std::vector<Vec3> worldCornerNormals(const std::vector<std::vector<Vec3>>& normals, size_t f,
                                     const Transform& transform, const Plane& plane) {
  std::vector<Vec3> out;
  if (normals.empty()) return out;
  // Normals map by the inverse transpose of R·S, which is R·S⁻¹.
  const Mat3 rotation = transform.rotation();
  for (const Vec3& n : normals.at(f)) {
    const Vec3 world = glm::normalize(rotation * (n / transform.scale));
    // Strictly in front, with room: a normal in the face's plane would take no light at all
    // from a light in front of the face, which no model means.
    if (!(glm::dot(world, plane.normal) > 1e-3)) return {};
    out.push_back(world);
  }
  if (transform.mirrors()) std::reverse(out.begin(), out.end());
  return out;
}

Vec3 interpolatedNormal(const Polygon3& polygon, const std::vector<Vec3>& corners, const Vec3& flat,
                        const Vec3& p) {
  if (corners.empty() || corners.size() != polygon.size()) return flat;
  // Barycentric weights from signed areas about the face's normal, per fan triangle.
  double best = -std::numeric_limits<double>::infinity();
  size_t bestI = 1;
  double weights[3] = {1, 0, 0};
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    const Vec3 &a = polygon[0], &b = polygon[i], &c = polygon[i + 1];
    const double whole = glm::dot(flat, glm::cross(b - a, c - a));
    if (!(std::abs(whole) > 0)) continue;
    const double wa = glm::dot(flat, glm::cross(b - p, c - p)) / whole;
    const double wb = glm::dot(flat, glm::cross(c - p, a - p)) / whole;
    const double wc = 1 - wa - wb;
    const double least = std::min({wa, wb, wc});
    if (least > best) {
      best = least;
      bestI = i;
      weights[0] = wa, weights[1] = wb, weights[2] = wc;
    }
  }
  // Just outside the triangle (p on an edge, within rounding): the nearest point's weights.
  double sum = 0;
  for (double& w : weights) sum += (w = std::max(0.0, w));
  if (!(sum > 0)) return flat;
  const Vec3 n = (weights[0] * corners[0] + weights[1] * corners[bestI] + weights[2] * corners[bestI + 1]) / sum;
  const double length = glm::length(n);
  return length > 0 ? n / length : flat;
}

std::vector<std::vector<Vec3>> smoothCornerNormals(const std::vector<Vec3>& vertices,
                                                   const std::vector<std::vector<int>>& faces,
                                                   double creaseDeg) {
  // Each face's unit normal (Newell) and the angle at each of its corners.
  std::vector<Vec3> faceNormal(faces.size(), Vec3(0.0));
  std::vector<std::vector<double>> cornerAngle(faces.size());
  std::vector<std::vector<size_t>> facesAt(vertices.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::vector<int>& face = faces[f];
    Vec3 newell(0.0);
    for (size_t k = 0; k < face.size(); ++k) {
      const Vec3 &a = vertices[size_t(face[k])], &b = vertices[size_t(face[(k + 1) % face.size()])];
      newell += glm::cross(a, b);
    }
    const double length = glm::length(newell);
    if (length > 0) faceNormal[f] = newell / length;
    for (size_t k = 0; k < face.size(); ++k) {
      const Vec3& c = vertices[size_t(face[k])];
      const Vec3 a = vertices[size_t(face[(k + face.size() - 1) % face.size()])] - c;
      const Vec3 b = vertices[size_t(face[(k + 1) % face.size()])] - c;
      cornerAngle[f].push_back(std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b)));
      facesAt[size_t(face[k])].push_back(f);
    }
  }
  const double cosCrease = std::cos(creaseDeg * 3.14159265358979323846 / 180);
  std::vector<std::vector<Vec3>> out(faces.size());
  for (size_t f = 0; f < faces.size(); ++f)
    for (size_t k = 0; k < faces[f].size(); ++k) {
      const Vec3& own = faceNormal[f];
      Vec3 sum(0.0);
      for (size_t g : facesAt[size_t(faces[f][k])]) {
        if (!(glm::dot(faceNormal[g], own) >= cosCrease)) continue;
        const auto at = std::find(faces[g].begin(), faces[g].end(), faces[f][k]) - faces[g].begin();
        sum += cornerAngle[g][size_t(at)] * faceNormal[g];
      }
      const double length = glm::length(sum);
      out[f].push_back(length > 0 ? sum / length : (glm::length(own) > 0 ? own : Vec3(0, 0, 1)));
    }
  return out;
}

}  // namespace penumbra
