#include "core/mesh/mesh.h"

namespace penumbra {

void appendMesh(ReceiverMesh& into, const ReceiverMesh& part) {
  const uint32_t offset = uint32_t(into.positions.size());
  into.positions.insert(into.positions.end(), part.positions.begin(), part.positions.end());
  into.irradiance.insert(into.irradiance.end(), part.irradiance.begin(), part.irradiance.end());
  into.classes.insert(into.classes.end(), part.classes.begin(), part.classes.end());
  into.triangles.reserve(into.triangles.size() + part.triangles.size());
  for (const auto& t : part.triangles) into.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
}

size_t Mesh::vertexCount() const {
  size_t n = 0;
  for (const auto& r : receivers) n += r.positions.size();
  return n;
}

size_t Mesh::triangleCount() const {
  size_t n = 0;
  for (const auto& r : receivers) n += r.triangles.size();
  return n;
}

}  // namespace penumbra
