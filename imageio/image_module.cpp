// The image module: PNG/EXR encoding with OpenImageIO behind the C interface of
// image_module_abi.h. Built as libpenumbra_image.so so that only processes writing images load
// OpenImageIO and its ~250 dependent libraries.
#include "imageio/image_module_abi.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <cstdio>
#include <exception>
#include <string>
#include <vector>

namespace {

void copyMessage(const std::string& message, char* error, size_t errorSize) {
  if (errorSize > 0) std::snprintf(error, errorSize, "%s", message.c_str());
}

// Throws std::runtime_error with OIIO's message on failure.
std::vector<unsigned char> encode(const std::string& format, int width, int height, bool isFloat,
                                  const void* pixels) {
  const OIIO::TypeDesc type = isFloat ? OIIO::TypeDesc::FLOAT : OIIO::TypeDesc::UINT8;
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  // The name only picks the plugin; bytes go to the proxy.
  auto out = OIIO::ImageOutput::create("image." + format);
  if (!out) throw std::runtime_error(format + ": " + OIIO::geterror());
  if (!out->set_ioproxy(&memory)) throw std::runtime_error(format + ": OIIO writer cannot write to memory");
  OIIO::ImageSpec spec(width, height, 3, type);
  if (!isFloat) {
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("oiio:ColorSpace", "sRGB");
  } else {
    spec.attribute("oiio:ColorSpace", "Linear");
  }
  if (!out->open("image." + format, spec) || !out->write_image(type, pixels) || !out->close())
    throw std::runtime_error(format + ": " + out->geterror());
  return bytes;
}

}  // namespace

extern "C" {

__attribute__((visibility("default"))) int penumbra_image_abi_version(void) {
  return PENUMBRA_IMAGE_ABI_VERSION;
}

__attribute__((visibility("default"))) int penumbra_image_encode(const char* format, int width, int height,
                                                                 int is_float, const void* pixels,
                                                                 penumbra_image_sink sink, void* context,
                                                                 char* error, size_t error_size) {
  try {
    const std::vector<unsigned char> bytes = encode(format, width, height, is_float != 0, pixels);
    sink(context, bytes.data(), bytes.size());
    return 0;
  } catch (const std::exception& failure) {
    copyMessage(failure.what(), error, error_size);
  } catch (...) {
    copyMessage(std::string(format) + ": unknown failure in OpenImageIO", error, error_size);
  }
  return 1;
}

}  // extern "C"
