// Lit mesh → glTF 2.0 binary (GLB) through tinygltf: one mesh per object with
// POSITION, linear COLOR_0 = outgoing radiance × a documented scale, and an
// unlit material (KHR_materials_unlit), so viewers show the baked light as is.
// Free functions; thread-safe.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra::interchange {

using Segment3 = std::array<Vec3, 2>;

struct GlbOptions {
  // COLOR_0 = radiance × colorScale, radiance = albedo / π × irradiance
  // (W·m⁻²·sr⁻¹, linear, not tone-mapped). 0: 1 / the largest channel of any
  // receiver vertex's radiance, so the brightest vertex is 1.
  double colorScale = 0;
  bool lights = true;           // a mesh "lights": the light polygons, COLOR_0 = radiance × colorScale
  std::vector<Segment3> edges;  // non-empty: a mesh "discontinuities" of LINES (dmEdges())
  // Not null: indirect irradiance per vertex (gi::vertexIndirect of the same mesh, same shape),
  // added to the direct one: radiance = albedo / π × (E_direct + E_indirect).
  const Mesh* indirect = nullptr;
};

struct GlbFile {
  std::vector<uint8_t> bytes;
  double colorScale = 1;  // the scale used (also in asset.extras.penumbra.color_scale)
  size_t meshes = 0, vertices = 0, triangles = 0;
};

// Every face of every object is in its object's mesh: receivers with their mesh
// vertices, faces that receive no light as black triangles. Throws std::invalid_argument when
// options.indirect has not the mesh's receivers.
GlbFile meshToGlb(const Scene& scene, const Mesh& mesh, const GlbOptions& options = {});
// Throws std::runtime_error when the file cannot be written.
GlbFile saveMeshGlb(const Scene& scene, const Mesh& mesh, const std::string& path, const GlbOptions& options = {});

}  // namespace penumbra::interchange
