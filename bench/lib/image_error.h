// Error of noisy images against a reference over a pixel mask, and the time an estimator needs
// to reach an error (log–log interpolation of its error-vs-time ladder). Pure functions of
// plain values; thread-safe.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

namespace penumbra {

// Mean squared difference per channel over the masked pixels (RGB, 3 floats per pixel).
double meanSquaredError(const std::vector<float>& image, const std::vector<float>& reference,
                        const std::vector<uint8_t>& mask);
// Mean of the masked pixels' channels (to make errors relative).
double maskedMean(const std::vector<float>& image, const std::vector<uint8_t>& mask);

// One rung of a sample ladder: wall seconds of one image and its relative RMS error.
struct LadderPoint {
  int samples = 0;
  double seconds = 0;
  double rms = 0;
};

struct TimeToError {
  double seconds = 0;
  bool extrapolated = false;  // beyond the ladder: the last two rungs' log–log slope
  bool firstRung = false;     // the first rung is already as good: its time (the least it costs)
};

// The time at which the ladder (errors falling as samples grow) reaches `rms`; nothing with
// fewer than two rungs or a non-falling end.
std::optional<TimeToError> timeToReach(const std::vector<LadderPoint>& ladder, double rms);

// A false-colour heat map of |image − reference| (mean over channels) / scale: black → red →
// yellow → white at 1; unmasked pixels are dark grey. 3 bytes per pixel.
std::vector<uint8_t> errorHeatMap(const std::vector<float>& image,
                                  const std::vector<float>& reference,
                                  const std::vector<uint8_t>& mask, double scale);

}  // namespace penumbra
