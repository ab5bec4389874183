#include "server/image_encoding.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace penumbra::server {

namespace {

std::vector<uint8_t> encode(const RenderedImage& image, const char* format, OIIO::TypeDesc type,
                            const void* pixels) {
  if (image.width <= 0 || image.height <= 0)
    throw ImageEncodingError(std::string(format) + ": empty image");
  std::vector<unsigned char> bytes;
  OIIO::Filesystem::IOVecOutput memory(bytes);
  // The name only picks the plugin; bytes go to the proxy.
  auto out = OIIO::ImageOutput::create(std::string("image.") + format);
  if (!out) throw ImageEncodingError(std::string(format) + ": " + OIIO::geterror());
  if (!out->set_ioproxy(&memory))
    throw ImageEncodingError(std::string(format) + ": OIIO writer cannot write to memory");
  OIIO::ImageSpec spec(image.width, image.height, 3, type);
  if (type == OIIO::TypeDesc::UINT8) {
    spec.attribute("png:compressionLevel", 1);
    spec.attribute("oiio:ColorSpace", "sRGB");
  } else {
    spec.attribute("oiio:ColorSpace", "Linear");
  }
  if (!out->open("image." + std::string(format), spec) || !out->write_image(type, pixels) || !out->close())
    throw ImageEncodingError(std::string(format) + ": " + out->geterror());
  return std::vector<uint8_t>(bytes.begin(), bytes.end());
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
  return encode(image, "png", OIIO::TypeDesc::UINT8, image.srgb.data());
}

std::vector<uint8_t> encodeExr(const RenderedImage& image) {
  if (image.linear.size() != 3 * size_t(image.width) * size_t(image.height))
    throw ImageEncodingError("exr: pixel buffer does not match the image size");
  return encode(image, "exr", OIIO::TypeDesc::FLOAT, image.linear.data());
}

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

}  // namespace penumbra::server
