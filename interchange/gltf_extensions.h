// The glTF extensions that change how geometry is stored (issue 40): which required ones the
// importer reads, the file made loadable by tinygltf, and Draco-compressed primitives decoded
// (KHR_draco_mesh_compression, Debian's libdraco). EXT_meshopt_compression's buffer views are
// decoded in gltf_meshopt.h. KHR_mesh_quantization needs no decoding here: its integer, possibly
// normalized accessors are read as any accessor (gltf_import.cpp) and the node transforms scale
// them back.
// Free functions; thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <tiny_gltf.h>

#include "core/geom/vec.h"
#include "interchange/imported_geometry.h"

namespace penumbra::interchange {

// Throws protocol::ValidationError at "extensionsRequired[i]" for the first required extension
// the importer cannot read (its name in the message): a file that needs it would otherwise be
// read wrongly (compressed buffers as garbage) or not at all.
void checkRequiredExtensions(const tinygltf::Model& model);

// The file (GLB or glTF text, as given) as tinygltf 2.7 can load it: the `indices` of every
// KHR_draco_mesh_compression primitive left out (Draco files give that accessor no buffer view,
// which tinygltf refuses, and the triangles come from the Draco stream anyway), and
// EXT_meshopt_compression fallback buffers without data given a placeholder
// (placeholdMeshoptFallbacks). Files without either extension come back unchanged. Throws
// protocol::ValidationError on a GLB container or JSON it cannot read.
std::vector<uint8_t> readableByTinygltf(const std::vector<uint8_t>& bytes);

// A primitive's geometry as decoded: positions (the primitive's own space) and triangles.
struct DecodedPrimitive {
  std::vector<Vec3> positions;
  std::vector<IndexPolygon> triangles;
  std::vector<Vec3> normals;  // NORMAL per position; empty when the file has none
};

// The primitive's KHR_draco_mesh_compression geometry, or nullopt without the extension.
// Throws protocol::ValidationError under `path` when the stream does not decode, has no
// POSITION, or is not triangles.
std::optional<DecodedPrimitive> decodeDracoPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& primitive,
                                                     const std::string& path);

}  // namespace penumbra::interchange
