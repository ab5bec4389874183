// Interpolating a lit mesh at a point of a receiving face (barycentric, in the
// triangle that contains it), for mesh-quality benchmarks and tests. Builds a
// per-receiver index once; immutable afterwards, thread-safe to query.
#pragma once

#include <map>
#include <optional>

#include "core/mesh/mesh.h"

namespace penumbra {

class MeshInterpolator {
 public:
  explicit MeshInterpolator(const Mesh& mesh);
  // The mesh's irradiance at p on face `face`, or nullopt if no triangle holds p.
  std::optional<Vec3> at(FaceId face, const Vec3& p) const;

 private:
  const Mesh& mesh_;
  std::map<FaceId, size_t> receiverOf_;
};

}  // namespace penumbra
