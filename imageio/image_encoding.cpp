#include "imageio/image_encoding.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

#include "imageio/image_module_loader.h"

namespace penumbra::imageio {

namespace {

std::vector<uint8_t> encode(const RenderedImage& image, const char* format, bool isFloat, const void* pixels) {
  if (image.width <= 0 || image.height <= 0)
    throw ImageEncodingError(std::string(format) + ": empty image");
  const ImageModule& module = imageModule();
  std::vector<uint8_t> bytes;
  const penumbra_image_sink sink = [](void* context, const unsigned char* data, size_t size) {
    static_cast<std::vector<uint8_t>*>(context)->assign(data, data + size);
  };
  char error[512] = "";
  if (module.encode(format, image.width, image.height, isFloat, pixels, sink, &bytes, error, sizeof error))
    throw ImageEncodingError(error);
  return bytes;
}

}  // namespace

ImageFormat imageFormatForPath(const std::string& path) {
  std::string extension = std::filesystem::path(path).extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return char(std::tolower(c)); });
  if (extension == ".png") return ImageFormat::Png;
  if (extension == ".exr") return ImageFormat::Exr;
  throw std::invalid_argument("image '" + path + "': unknown extension (use .png or .exr)");
}

std::vector<uint8_t> encodePng(const RenderedImage& image) {
  if (image.srgb.size() != 3 * size_t(image.width) * size_t(image.height))
    throw ImageEncodingError("png: pixel buffer does not match the image size");
  return encode(image, "png", false, image.srgb.data());
}

std::vector<uint8_t> encodeExr(const RenderedImage& image) {
  if (image.linear.size() != 3 * size_t(image.width) * size_t(image.height))
    throw ImageEncodingError("exr: pixel buffer does not match the image size");
  return encode(image, "exr", true, image.linear.data());
}

void loadImageModule() { imageModule(); }

std::vector<uint8_t> encodeImage(const RenderedImage& image, ImageFormat format) {
  return format == ImageFormat::Png ? encodePng(image) : encodeExr(image);
}

void writeImageFile(const RenderedImage& image, const std::string& path) {
  const std::vector<uint8_t> bytes = encodeImage(image, imageFormatForPath(path));
  const std::string temporary = path + ".partial";
  {
    std::ofstream file(temporary, std::ios::binary | std::ios::trunc);
    file.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
    if (!file.good()) {
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw ImageEncodingError("cannot write '" + path + "'");
    }
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    throw ImageEncodingError("cannot write '" + path + "'");
  }
}

}  // namespace penumbra::imageio
