#include "core/gi/id_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra::gi {

std::vector<Vec3> idAwareGaussian(int width, int height, const std::vector<Vec3>& values,
                                  const std::vector<int32_t>& id, int radius, double sigma,
                                  const Parallel& parallel) {
  const size_t pixels = size_t(width) * size_t(height);
  if (values.size() != pixels || id.size() != pixels)
    throw std::invalid_argument("idAwareGaussian: buffers do not match the image size");
  if (radius < 0 || !(sigma > 0)) throw std::invalid_argument("idAwareGaussian: radius >= 0, sigma > 0");
  std::vector<double> kernel(size_t(radius) + 1);
  for (int d = 0; d <= radius; ++d) kernel[size_t(d)] = std::exp(-0.5 * d * d / (sigma * sigma));
  std::vector<Vec3> out(pixels, Vec3(0.0));
  parallel.forEach(size_t(height), [&](size_t row) {
    const int y = int(row);
    for (int x = 0; x < width; ++x) {
      const size_t p = row * size_t(width) + size_t(x);
      if (id[p] < 0) continue;
      Vec3 sum(0.0);
      double total = 0;
      for (int dy = -radius; dy <= radius; ++dy) {
        const int yy = y + dy;
        if (yy < 0 || yy >= height) continue;
        for (int dx = -radius; dx <= radius; ++dx) {
          const int xx = x + dx;
          if (xx < 0 || xx >= width) continue;
          const size_t q = size_t(yy) * size_t(width) + size_t(xx);
          if (id[q] != id[p]) continue;  // k_ij = 0 across surfaces
          const double k = kernel[size_t(std::abs(dx))] * kernel[size_t(std::abs(dy))];
          sum += k * values[q];
          total += k;
        }
      }
      out[p] = sum / total;  // total > 0: the pixel itself counts
    }
  });
  return out;
}

}  // namespace penumbra::gi
