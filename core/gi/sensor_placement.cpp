#include "core/gi/sensor_placement.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <mutex>
#include <stdexcept>

namespace penumbra::gi {

namespace {

struct Tile {
  int x0, y0, x1, y1;  // corner pixels, inclusive
};

enum class Filled : uint8_t { No, Interpolated, Sensed };

constexpr size_t kSensorsPerReport = 64;

class Placement {
 public:
  Placement(int width, int height, const std::vector<int32_t>& id, const std::function<Vec3(size_t)>& sense,
            const Parallel& parallel)
      : w_(width), h_(height), id_(id), sense_(sense), parallel_(parallel),
        value_(size_t(width) * size_t(height), Vec3(0.0)), filled_(value_.size(), Filled::No) {}

  // Senses every listed pixel not yet sensed; returns how many. report(sensed so far in this
  // call) every kSensorsPerReport sensors, one call at a time and counting up, from whichever
  // thread reaches the count: a level holds up to ~10⁵ sensors (seconds), and a report is where
  // a render learns it was cancelled (report may throw; the throw ends the loop).
  size_t senseAll(std::vector<size_t> pixels, const std::function<void(size_t sensed)>& report) {
    std::sort(pixels.begin(), pixels.end());
    pixels.erase(std::unique(pixels.begin(), pixels.end()), pixels.end());
    std::erase_if(pixels, [&](size_t p) { return id_[p] < 0 || filled_[p] == Filled::Sensed; });
    std::atomic<size_t> sensed{0};
    std::mutex reporting;
    size_t reported = 0;
    parallel_.forEach(pixels.size(), [&](size_t k) {
      value_[pixels[k]] = sense_(pixels[k]);
      const size_t done = sensed.fetch_add(1) + 1;
      if (!report || done % kSensorsPerReport != 0) return;
      std::lock_guard lock(reporting);
      if (done > reported) report(reported = done);
    });
    for (size_t p : pixels) filled_[p] = Filled::Sensed;
    return pixels.size();
  }

  size_t at(int x, int y) const { return size_t(y) * size_t(w_) + size_t(x); }

  // Interpolates a tile whose corners are sensed, lie on one surface and agree (false: they
  // do not); pixels inside that lie on another surface go to `strays` (sensed at the end).
  bool tryInterpolate(const Tile& t, double threshold, std::vector<size_t>& strays, size_t& interpolated) {
    const size_t c[4] = {at(t.x0, t.y0), at(t.x1, t.y0), at(t.x0, t.y1), at(t.x1, t.y1)};
    const int32_t surface = id_[c[0]];
    for (size_t k : c)
      if (id_[k] < 0 || id_[k] != surface) return false;
    const Vec3 v[4] = {value_[c[0]], value_[c[1]], value_[c[2]], value_[c[3]]};
    if (relativeSpread(v, 4) > threshold) return false;
    for (int y = t.y0; y <= t.y1; ++y) {
      const double fy = t.y1 > t.y0 ? double(y - t.y0) / (t.y1 - t.y0) : 0;
      for (int x = t.x0; x <= t.x1; ++x) {
        const size_t p = at(x, y);
        if (filled_[p] == Filled::Sensed) continue;
        if (id_[p] != surface) {
          if (id_[p] >= 0) strays.push_back(p);
          continue;
        }
        const double fx = t.x1 > t.x0 ? double(x - t.x0) / (t.x1 - t.x0) : 0;
        value_[p] = (1 - fy) * ((1 - fx) * v[0] + fx * v[1]) + fy * ((1 - fx) * v[2] + fx * v[3]);
        if (filled_[p] == Filled::No) ++interpolated;
        filled_[p] = Filled::Interpolated;
      }
    }
    return true;
  }

  std::vector<Vec3> take() { return std::move(value_); }

 private:
  int w_, h_;
  const std::vector<int32_t>& id_;
  const std::function<Vec3(size_t)>& sense_;
  const Parallel& parallel_;
  std::vector<Vec3> value_;
  std::vector<Filled> filled_;
};

// Left (or top) corners of the first tiles along a side of n pixels: 0, tile, … short of n − 1.
std::vector<int> tileStarts(int n, int tile) {
  std::vector<int> starts;
  for (int x = 0; x == 0 || x < n - 1; x += tile) starts.push_back(x);
  return starts;
}

std::vector<Tile> firstTiles(int width, int height, int tile) {
  std::vector<Tile> tiles;
  for (int y : tileStarts(height, tile))
    for (int x : tileStarts(width, tile))
      tiles.push_back({x, y, std::min(x + tile, width - 1), std::min(y + tile, height - 1)});
  return tiles;
}

// The four quarters of a tile (fewer when it is one pixel wide or high).
void split(const Tile& t, std::vector<Tile>& out) {
  const int mx = (t.x0 + t.x1) / 2, my = (t.y0 + t.y1) / 2;
  const bool wide = t.x1 - t.x0 > 1, high = t.y1 - t.y0 > 1;
  for (const auto& [xa, xb] : wide ? std::vector<std::pair<int, int>>{{t.x0, mx}, {mx, t.x1}}
                                   : std::vector<std::pair<int, int>>{{t.x0, t.x1}})
    for (const auto& [ya, yb] : high ? std::vector<std::pair<int, int>>{{t.y0, my}, {my, t.y1}}
                                     : std::vector<std::pair<int, int>>{{t.y0, t.y1}})
      out.push_back({xa, ya, xb, yb});
}

}  // namespace

double relativeSpread(const Vec3* values, size_t n) {
  Vec3 mean(0.0);
  for (size_t k = 0; k < n; ++k) mean += values[k];
  mean /= double(n);
  const double scale = std::max({mean.x, mean.y, mean.z});
  double spread = 0;
  for (size_t k = 0; k < n; ++k) {
    const Vec3 d = glm::abs(values[k] - mean);
    spread = std::max({spread, d.x, d.y, d.z});
  }
  if (spread == 0) return 0;
  return scale > 0 ? spread / scale : INFINITY;
}

std::vector<Vec3> placeSensors(int width, int height, const std::vector<int32_t>& id,
                               const std::function<Vec3(size_t pixel)>& sense, const PlacementSettings& settings,
                               const Parallel& parallel, PlacementStats& stats,
                               const std::function<void(size_t sensors)>& progress) {
  if (width < 1 || height < 1 || id.size() != size_t(width) * size_t(height))
    throw std::invalid_argument("placeSensors: the id buffer does not match the image size");
  if (settings.tile < 1 || !(settings.threshold >= 0))
    throw std::invalid_argument("placeSensors: tile must be >= 1 and threshold >= 0");
  stats = PlacementStats{};
  Placement placement(width, height, id, sense, parallel);
  std::vector<Tile> tiles = firstTiles(width, height, settings.tile);
  std::vector<size_t> strays;
  const std::function<void(size_t)> withinLevel =
      progress ? std::function<void(size_t)>([&](size_t sensed) { progress(stats.sensors + sensed); }) : nullptr;
  while (!tiles.empty()) {
    std::vector<size_t> corners;
    for (const Tile& t : tiles)
      for (size_t c : {placement.at(t.x0, t.y0), placement.at(t.x1, t.y0), placement.at(t.x0, t.y1),
                       placement.at(t.x1, t.y1)})
        corners.push_back(c);
    stats.sensorsPerLevel.push_back(placement.senseAll(std::move(corners), withinLevel));
    stats.sensors += stats.sensorsPerLevel.back();
    if (progress) progress(stats.sensors);
    std::vector<Tile> next;
    for (const Tile& t : tiles) {
      const bool smallest = t.x1 - t.x0 <= 1 && t.y1 - t.y0 <= 1;
      if (!placement.tryInterpolate(t, settings.threshold, strays, stats.interpolated) && !smallest) split(t, next);
    }
    tiles = std::move(next);
  }
  // Pixels inside interpolated tiles that lie on another surface than the tile's corners.
  stats.sensorsPerLevel.push_back(placement.senseAll(std::move(strays), withinLevel));
  stats.sensors += stats.sensorsPerLevel.back();
  if (progress) progress(stats.sensors);
  return placement.take();
}

}  // namespace penumbra::gi
