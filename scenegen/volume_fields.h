// Generators of test scalar fields for core/volume (issue 15): Marschner–Lobb, a sphere
// distance field, fractal-noise smoke and a sharp two-fluid mixing layer, at any size, as
// float in [0, 1] or quantised to 8 or 16 bits. Pure and seeded; thread-safe.
#pragma once

#include <cstdint>
#include <glm/glm.hpp>
#include <string>

#include "core/geom/vec.h"
#include "core/volume/dense_grid.h"

namespace penumbra {

enum class VolumeField { MarschnerLobb, Sphere, Smoke, MixingLayer };
inline constexpr VolumeField kVolumeFields[] = {VolumeField::MarschnerLobb, VolumeField::Sphere,
                                                VolumeField::Smoke, VolumeField::MixingLayer};
std::string volumeFieldName(VolumeField field);  // "marschner-lobb", "sphere", "smoke", "mixing"

struct VolumeFieldSpec {
  VolumeField field = VolumeField::MarschnerLobb;
  glm::ivec3 size{64};
  uint64_t seed = 1;  // smoke and mixing layer noise
};

// The sphere field is linear in the distance to the sphere: value = 0.5 + (R − |p − c|) / (2·n)
// with n the largest side; its 0.5 isosurface is the sphere (voxel coordinates).
struct SphereGeometry {
  Vec3 centre;
  double radius;
  double valuePerVoxel;  // |gradient| of the field, 1 / (2 n)
};
SphereGeometry sphereGeometry(glm::ivec3 size);

volume::DenseGrid<float> makeVolumeField(const VolumeFieldSpec& spec);
volume::DenseGrid<uint8_t> quantise8(const volume::DenseGrid<float>& field);    // round(v · 255)
volume::DenseGrid<uint16_t> quantise16(const volume::DenseGrid<float>& field);  // round(v · 65535)

}  // namespace penumbra
