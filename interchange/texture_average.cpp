#include "interchange/texture_average.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace penumbra::interchange {

namespace {

double linearFromSrgb(double c) {
  return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// The texel's colour in [0, 1], still sRGB-encoded; grey images give grey.
Vec3 texel(const tinygltf::Image& image, int x, int y) {
  const size_t channels = size_t(image.component), bytes = image.bits == 16 ? 2 : 1;
  const unsigned char* p =
      image.image.data() + (size_t(y) * size_t(image.width) + size_t(x)) * channels * bytes;
  auto channel = [&](size_t c) {
    if (bytes == 1) return p[c] / 255.0;
    uint16_t v;
    std::memcpy(&v, p + 2 * c, 2);
    return v / 65535.0;
  };
  return channels >= 3 ? Vec3(channel(0), channel(1), channel(2)) : Vec3(channel(0));
}

}  // namespace

std::optional<Vec3> averageTextureColour(const tinygltf::Image& image, const std::vector<Vec2>& uvs,
                                         const std::vector<Vec3>& positions,
                                         const std::vector<IndexPolygon>& triangles) {
  const size_t bytes = image.bits == 16 ? 2 : 1;
  if (image.width <= 0 || image.height <= 0 || image.component <= 0 ||
      image.image.size() <
          size_t(image.width) * size_t(image.height) * size_t(image.component) * bytes)
    return std::nullopt;
  const Vec2 texels(image.width, image.height);
  auto sample = [&](const Vec2& uv) {
    const Vec2 wrapped = uv - glm::floor(uv);  // REPEAT
    const int x = std::min(image.width - 1, int(wrapped.x * texels.x));
    const int y = std::min(image.height - 1, int(wrapped.y * texels.y));  // v = 0 is the top row
    const Vec3 c = texel(image, x, y);
    return Vec3(linearFromSrgb(c.x), linearFromSrgb(c.y), linearFromSrgb(c.z));
  };
  Vec3 sum(0.0);
  double totalArea = 0;
  for (const IndexPolygon& t : triangles) {
    const Vec3 &a = positions[size_t(t[0])], &b = positions[size_t(t[1])],
               &c = positions[size_t(t[2])];
    const double area = 0.5 * glm::length(glm::cross(b - a, c - a));
    if (!(area > 0)) continue;
    const Vec2 &ua = uvs[size_t(t[0])], &ub = uvs[size_t(t[1])], &uc = uvs[size_t(t[2])];
    const double longest =
        std::max({glm::length((ub - ua) * texels), glm::length((uc - ub) * texels),
                  glm::length((ua - uc) * texels)});
    const int n = std::isfinite(longest) ? int(std::clamp(std::ceil(longest), 1.0, 32.0)) : 32;
    // The centroids of the n² sub-triangles of a regular subdivision (all of one area).
    Vec3 colour(0.0);
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        for (const double offset : {1.0 / 3, 2.0 / 3}) {
          if (offset > 0.5 && i + j > n - 2) continue;  // downward sub-triangles: one row fewer
          const double s = (i + offset) / n, r = (j + offset) / n;
          colour += sample(ua + s * (ub - ua) + r * (uc - ua));
        }
      }
    sum += area * colour / double(n * n);
    totalArea += area;
  }
  if (!(totalArea > 0)) return std::nullopt;
  return sum / totalArea;
}

std::optional<std::pair<int, int>> encodedImageSize(const unsigned char* bytes, size_t size) {
  auto big16 = [&](size_t at) { return int(bytes[at]) << 8 | int(bytes[at + 1]); };
  static const unsigned char kPng[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  if (size >= 24 && std::memcmp(bytes, kPng, 8) == 0)  // IHDR: width and height, big-endian 32-bit
    return std::pair{big16(16) << 16 | big16(18), big16(20) << 16 | big16(22)};
  if (size < 4 || bytes[0] != 0xff || bytes[1] != 0xd8) return std::nullopt;
  // JPEG: walk the segments to the first start-of-frame (SOF0–SOF15 but DHT, JPG and DAC).
  for (size_t at = 2; at + 9 < size;) {
    if (bytes[at] != 0xff) return std::nullopt;
    const unsigned char marker = bytes[at + 1];
    if (marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc)
      return std::pair{big16(at + 7), big16(at + 5)};
    at += 2 + size_t(big16(at + 2));
  }
  return std::nullopt;
}

}  // namespace penumbra::interchange
