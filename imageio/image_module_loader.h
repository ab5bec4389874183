// Finds and loads the image module (libpenumbra_image.so) once per process, on first use:
// $PENUMBRA_IMAGE_MODULE if set, else the file next to the running executable. Thread-safe.
#pragma once

#include <string>

#include "imageio/image_module_abi.h"

namespace penumbra::imageio {

inline constexpr const char* kImageModuleFile = "libpenumbra_image.so";

struct ImageModule {
  std::string path;  // where it was loaded from
  penumbra_image_encode_fn encode = nullptr;
};

// The loaded module; kept loaded until exit. Throws ImageEncodingError (image_encoding.h) naming
// the path tried and why it failed (missing file, unresolved symbol, other ABI version); a failed
// load is not retried.
const ImageModule& imageModule();

}  // namespace penumbra::imageio
