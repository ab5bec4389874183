// EXT_meshopt_compression (issue 40): buffer views stored compressed by meshoptimizer's codecs,
// decoded with Debian's libmeshoptimizer before any accessor reads them. A view's extension names
// where its compressed bytes lie (buffer, byteOffset, byteLength), what they decode to (count
// elements of byteStride bytes) and how (mode ATTRIBUTES, TRIANGLES or INDICES; filter NONE,
// OCTAHEDRAL, QUATERNION or EXPONENTIAL); the view's own buffer is a fallback that may hold no
// data. Free functions; thread-safe.
#pragma once

#include <tiny_gltf.h>

#include <cstddef>
#include <nlohmann/json.hpp>

namespace penumbra::interchange {

// Gives every fallback buffer without data (extensions.EXT_meshopt_compression.fallback, no uri)
// a 4-byte placeholder so tinygltf 2.7 loads the file: it refuses a buffer without a uri in glTF
// text, and in a GLB hands it the BIN chunk or refuses it when that is shorter. Whether any
// buffer changed. Every view over such a buffer is compressed, and decodeMeshoptViews repoints it.
bool placeholdMeshoptFallbacks(nlohmann::json& gltf);

// Decodes every buffer view with the extension into a buffer of its own (appended to
// model.buffers) and points the view at it: accessors then read plain data. The number of views
// decoded. Throws protocol::ValidationError at "bufferViews[i].extensions.EXT_meshopt_compression…"
// on a stream that does not decode, a mode, filter or stride the codec does not have, compressed
// bytes past their buffer, or more than 256 MiB decoded in all.
size_t decodeMeshoptViews(tinygltf::Model& model);

}  // namespace penumbra::interchange
