// A base colour texture folded into one albedo (issue 40): the scene gives each object one
// material, so a textured primitive's albedo is its base colour factor times the texture's
// linear colour averaged over its triangles (weighted by their area). Also the guard on decoding
// textures from untrusted files. Free functions; thread-safe.
#pragma once

#include <tiny_gltf.h>

#include <optional>
#include <vector>

#include "core/geom/vec.h"
#include "interchange/polygon_repair.h"

namespace penumbra::interchange {

// The texture's colour (sRGB-decoded to linear, alpha ignored) averaged over the triangles:
// each sampled at n² equal sub-triangles (n: its longest edge in texels, 1 to 32), nearest
// texel, UVs (finite) wrapped (glTF's default sampler). nullopt when the image has no pixels or the
// triangles no area.
std::optional<Vec3> averageTextureColour(const tinygltf::Image& image, const std::vector<Vec2>& uvs,
                                         const std::vector<Vec3>& positions,
                                         const std::vector<IndexPolygon>& triangles);

// Pixels the importer decodes per file, all images together (a 256 MiB file could otherwise
// hold images that decode to many GiB): 64 Mi, e.g. four 4096² textures.
inline constexpr size_t kMaxTexturePixels = size_t(64) << 20;

// Width and height from a PNG or JPEG header; nullopt for anything else.
std::optional<std::pair<int, int>> encodedImageSize(const unsigned char* bytes, size_t size);

}  // namespace penumbra::interchange
