// Lit meshes per receiving face: positions, per-vertex irradiance and class,
// triangles. Produced by the reference grid and (later) the DM engine; plain data.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/illum/light_class.h"
#include "core/scene/scene.h"

namespace penumbra {

struct ReceiverMesh {
  FaceId face;
  Vec3 normal{0.0};
  std::vector<Vec3> positions;
  std::vector<Vec3> irradiance;  // RGB, W·m⁻², summed over lights
  std::vector<LightClass> classes;
  std::vector<std::array<uint32_t, 3>> triangles;  // CCW seen from the front
};

// Appends `part`'s vertices and triangles to `into` (indices shifted): a receiver's
// mesh from its display chunks.
void appendMesh(ReceiverMesh& into, const ReceiverMesh& part);

struct Mesh {
  std::vector<ReceiverMesh> receivers;
  // What interpolation inside its triangles is within (EngineSettings::meshTolerance): the
  // fraction of each light's local unshadowed level at the refinement's test points (0: not
  // refined, or unknown), and the cells whose refinement stopped at its point cap short of it.
  double tolerance = 0;
  size_t cappedCells = 0;
  size_t vertexCount() const;
  size_t triangleCount() const;
};

}  // namespace penumbra
