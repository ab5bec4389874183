// Lit mesh → glTF 2.0 binary (GLB) through tinygltf, valid for the Khronos glTF-Validator
// (issue 40). One mesh and node per object, named by its id, with POSITION, COLOR_0 = the
// display colour in [0, 1] (the page's exposure: min(1, color_scale · albedo/π · (E + fill)),
// fill = the indirect irradiance when given, else the ambient fill, core/illum/ambient_fill.h)
// on an unlit material (KHR_materials_unlit), and the exact values losslessly in application
// attributes: _IRRADIANCE = the direct irradiance E (W·m⁻²), _RADIANCE = albedo/π · (E + the
// indirect irradiance when given) (W·m⁻²·sr⁻¹), both float RGB. Each light is a mesh and node
// named by its id with an emissive material: emissiveFactor = its radiance over its largest
// channel, KHR_materials_emissive_strength = that channel × color_scale (the colour it would
// have in COLOR_0, unclamped). The scene's camera (or the default view of its bounds) is a
// camera node. For the round trip (docs/SCENE_FORMAT.md "GLB round trip", penumbra_extras.h):
// _FACE = each vertex's face index within its object, and each scene material its own (white,
// unlit) glTF material carrying the material in extras.penumbra. Free functions; thread-safe.
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
  // COLOR_0 = min(1, colorScale × albedo/π × (E + fill)), linear. 0: the page's automatic
  // exposure, 1 / the 99th percentile over the receivers' vertices of that radiance's largest
  // channel.
  double colorScale = 0;
  bool lights = true;           // a mesh per light: its polygon, emissive (see above)
  std::vector<Segment3> edges;  // non-empty: a mesh "discontinuities" of LINES (dmEdges())
  // Not null: indirect irradiance per vertex (gi::vertexIndirect of the same mesh, same shape):
  // the fill of COLOR_0 and added to _RADIANCE (albedo / π × (E_direct + E_indirect)).
  const Mesh* indirect = nullptr;
};

struct GlbFile {
  std::vector<uint8_t> bytes;
  double colorScale = 1;  // the scale used (also in asset.extras.penumbra.color_scale)
  Vec3 ambient{0.0};      // the fill used without indirect light (asset.extras.penumbra.ambient)
  size_t meshes = 0, vertices = 0, triangles = 0;
};

// Every face of every object is in its object's mesh: receivers with their mesh
// vertices, faces that receive no light as black triangles. Throws std::invalid_argument when
// options.indirect has not the mesh's receivers.
GlbFile meshToGlb(const Scene& scene, const Mesh& mesh, const GlbOptions& options = {});
// Throws std::runtime_error when the file cannot be written.
GlbFile saveMeshGlb(const Scene& scene, const Mesh& mesh, const std::string& path, const GlbOptions& options = {});

}  // namespace penumbra::interchange
