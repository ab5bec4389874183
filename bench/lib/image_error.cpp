#include "bench/lib/image_error.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

double meanSquaredError(const std::vector<float>& image, const std::vector<float>& reference,
                        const std::vector<uint8_t>& mask) {
  double sum = 0;
  size_t count = 0;
  for (size_t p = 0; p < mask.size(); ++p) {
    if (!mask[p]) continue;
    for (size_t c = 0; c < 3; ++c) {
      const double d = double(image[3 * p + c]) - double(reference[3 * p + c]);
      sum += d * d;
    }
    count += 3;
  }
  return count ? sum / double(count) : 0.0;
}

double maskedMean(const std::vector<float>& image, const std::vector<uint8_t>& mask) {
  double sum = 0;
  size_t count = 0;
  for (size_t p = 0; p < mask.size(); ++p)
    if (mask[p]) {
      sum += double(image[3 * p]) + double(image[3 * p + 1]) + double(image[3 * p + 2]);
      count += 3;
    }
  return count ? sum / double(count) : 0.0;
}

std::optional<TimeToError> timeToReach(const std::vector<LadderPoint>& ladder, double rms) {
  if (ladder.size() < 2 || !(rms > 0)) return std::nullopt;
  // Log–log line through two rungs, evaluated at rms.
  auto along = [&](const LadderPoint& a, const LadderPoint& b) -> std::optional<double> {
    if (!(a.rms > 0 && b.rms > 0 && a.seconds > 0 && b.seconds > 0) || a.rms == b.rms)
      return std::nullopt;
    const double slope =
        (std::log(b.seconds) - std::log(a.seconds)) / (std::log(b.rms) - std::log(a.rms));
    return std::exp(std::log(a.seconds) + slope * (std::log(rms) - std::log(a.rms)));
  };
  // Fewer samples than the first rung's are not measured (one is the least): its time.
  if (rms >= ladder.front().rms) return TimeToError{ladder.front().seconds, false, true};
  for (size_t k = 1; k < ladder.size(); ++k)
    if (ladder[k].rms <= rms) {
      const auto t = along(ladder[k - 1], ladder[k]);
      if (!t) return TimeToError{ladder[k].seconds, false};
      return TimeToError{*t, false};
    }
  const LadderPoint& a = ladder[ladder.size() - 2];
  const LadderPoint& b = ladder.back();
  if (!(b.rms < a.rms)) return std::nullopt;
  const auto t = along(a, b);
  if (!t) return std::nullopt;
  return TimeToError{*t, true};
}

std::vector<uint8_t> errorHeatMap(const std::vector<float>& image,
                                  const std::vector<float>& reference,
                                  const std::vector<uint8_t>& mask, double scale) {
  std::vector<uint8_t> out(3 * mask.size(), 40);
  for (size_t p = 0; p < mask.size(); ++p) {
    if (!mask[p]) continue;
    double e = 0;
    for (size_t c = 0; c < 3; ++c)
      e += std::abs(double(image[3 * p + c]) - double(reference[3 * p + c])) / 3;
    const double x = std::clamp(scale > 0 ? e / scale : 0.0, 0.0, 1.0);
    // black → red (1/3) → yellow (2/3) → white (1)
    const double r = std::clamp(3 * x, 0.0, 1.0), g = std::clamp(3 * x - 1, 0.0, 1.0),
                 b = std::clamp(3 * x - 2, 0.0, 1.0);
    out[3 * p] = uint8_t(std::lround(255 * r));
    out[3 * p + 1] = uint8_t(std::lround(255 * g));
    out[3 * p + 2] = uint8_t(std::lround(255 * b));
  }
  return out;
}

}  // namespace penumbra
