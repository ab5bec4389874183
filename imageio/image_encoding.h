// Rendered images to bytes with OpenImageIO: PNG (8-bit sRGB) and OpenEXR (linear float RGB),
// encoded in memory (for the CLI and the HTTP server) or written to a file chosen by extension.
// Free functions; thread-safe. OIIO lives in the image module, loaded on first use.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/render/renderer.h"

namespace penumbra::imageio {

// OIIO could not create a writer or encode (message from OIIO), the image module could not be
// loaded (message names its path), or the file could not be written.
class ImageEncodingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ImageFormat { Png, Exr };

// The format a path's extension names (.png, .exr; case-insensitive). Throws std::invalid_argument
// naming the path for any other extension.
ImageFormat imageFormatForPath(const std::string& path);

// Loads the image module now rather than at the first encode, so a command can refuse before
// its work when images are unavailable. Throws ImageEncodingError.
void loadImageModule();

// RenderedImage::srgb as PNG; compression level 1 (about 3× faster than the default, for
// interactive responses).
std::vector<uint8_t> encodePng(const RenderedImage& image);
// RenderedImage::linear as a 32-bit float RGB OpenEXR.
std::vector<uint8_t> encodeExr(const RenderedImage& image);
std::vector<uint8_t> encodeImage(const RenderedImage& image, ImageFormat format);

// Encodes by the path's extension and writes the bytes (a temporary file renamed into place, so
// a failed write leaves no half-written image).
void writeImageFile(const RenderedImage& image, const std::string& path);

}  // namespace penumbra::imageio
