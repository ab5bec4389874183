#include "imageio/image_module_loader.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <system_error>
#include <variant>

#include "imageio/image_encoding.h"

namespace penumbra::imageio {

namespace {

std::string modulePath() {
  if (const char* path = std::getenv("PENUMBRA_IMAGE_MODULE"); path && *path) return path;
  std::error_code error;
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error) return kImageModuleFile;  // no /proc: let dlopen search the library path
  return (executable.parent_path() / kImageModuleFile).string();
}

// The module, or why it could not be loaded.
std::variant<ImageModule, std::string> load() {
  ImageModule module;
  module.path = modulePath();
  const std::string hint = " (built next to the penumbra executable; set PENUMBRA_IMAGE_MODULE to use another)";
  // RTLD_NODELETE: OpenImageIO keeps threads and static state for the life of the process.
  void* handle = dlopen(module.path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_NODELETE);
  if (!handle) return "cannot load the image module '" + module.path + "': " + dlerror() + hint;
  const auto version = reinterpret_cast<penumbra_image_abi_version_fn>(dlsym(handle, "penumbra_image_abi_version"));
  module.encode = reinterpret_cast<penumbra_image_encode_fn>(dlsym(handle, "penumbra_image_encode"));
  if (!version || !module.encode)
    return "'" + module.path + "' is not a penumbra image module (missing symbols)" + hint;
  if (version() != PENUMBRA_IMAGE_ABI_VERSION)
    return "the image module '" + module.path + "' has interface version " + std::to_string(version()) +
           ", this penumbra needs " + std::to_string(PENUMBRA_IMAGE_ABI_VERSION) + hint;
  return module;
}

}  // namespace

const ImageModule& imageModule() {
  static const std::variant<ImageModule, std::string> loaded = load();
  if (const auto* failure = std::get_if<std::string>(&loaded)) throw ImageEncodingError(*failure);
  return std::get<ImageModule>(loaded);
}

}  // namespace penumbra::imageio
