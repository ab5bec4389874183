// The C interface of the image module (libpenumbra_image.so, image_module.cpp): the only code
// that links OpenImageIO, loaded by image_module_loader.cpp on first use. Stateless, thread-safe.
#pragma once

#include <cstddef>

// Bumped whenever a signature below changes; the loader refuses a module of another version.
#define PENUMBRA_IMAGE_ABI_VERSION 1

extern "C" {

// Receives the encoded bytes (called once, before penumbra_image_encode returns).
typedef void (*penumbra_image_sink)(void* context, const unsigned char* bytes, size_t size);

typedef int (*penumbra_image_abi_version_fn)(void);

// Encodes width × height interleaved RGB pixels (8-bit if !is_float, else 32-bit float) in the
// format named ("png": compression level 1, sRGB; "exr": linear). Returns 0 after handing the
// bytes to sink, or non-zero with a NUL-terminated message in error[0 .. error_size). Never
// throws across the boundary.
typedef int (*penumbra_image_encode_fn)(const char* format, int width, int height, int is_float,
                                        const void* pixels, penumbra_image_sink sink, void* context,
                                        char* error, size_t error_size);

}  // extern "C"
