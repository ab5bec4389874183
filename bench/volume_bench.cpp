// `penumbra-volume-bench [--sizes 64,128] [--render-size 128] [--res 512] [--threads 1,2]
// [--frames 2]`: the paper's Table 1 (octree size / raw size per field, 8- and 16-bit, with an
// iso-range clamp and a lossy row) and Table 2 (rays/s and frames/s at res² for octree
// traversal on octree data against the macrocell grid on the raw array). Progress on stderr.
#include <tbb/blocked_range2d.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "core/engine/seconds_since.h"
#include "core/volume/macrocell_grid.h"
#include "core/volume/octree_trace.h"
#include "scenegen/volume_fields.h"

namespace penumbra {
namespace {

using Clock = std::chrono::steady_clock;
std::vector<int> intList(const std::string& text) {
  std::vector<int> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) out.push_back(std::stoi(item));
  return out;
}

struct Options {
  std::vector<int> sizes{64, 128};
  int renderSize = 128;
  int res = 512;
  std::vector<int> threads{1, 2};
  int frames = 2;
};

template <class T>
void table1Row(const char* field, const char* kind, const volume::DenseGrid<T>& grid,
               const volume::OctreeBuildOptions& options) {
  const auto start = Clock::now();
  const auto octree = volume::OctreeVolume<T>::build(grid, options);
  const double seconds = secondsSince(start);
  const double voxels = double(grid.values.size());
  std::printf("| %-14s | %-13s | %4dx%dx%d | %10zu | %10zu | %5.1f | %8zu | %8zu | %6.1f |\n",
              field, kind, grid.size.x, grid.size.y, grid.size.z, grid.bytes(), octree.bytes(),
              100.0 * double(octree.bytes()) / double(grid.bytes()), octree.nodeCount(),
              octree.caps().size(), 1e9 * seconds / voxels);
}

volume::DenseGrid<uint8_t> clamped(volume::DenseGrid<uint8_t> grid, int lo, int hi) {
  for (uint8_t& v : grid.values) v = uint8_t(std::clamp(int(v), lo, hi));
  return grid;
}

void table1(const Options& options) {
  std::printf(
      "\nTable 1: octree volume size (nodes + caps + embedded min/max tree) / raw array\n\n");
  std::printf(
      "| field          | data          | size        | raw bytes  | octree B   | %%     |"
      " nodes    | caps     | ns/vox |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (int n : options.sizes)
    for (VolumeField field : kVolumeFields) {
      std::fprintf(stderr, "table 1: %s %d^3\n", volumeFieldName(field).c_str(), n);
      const auto f = makeVolumeField({field, glm::ivec3(n), 1});
      const std::string name = volumeFieldName(field);
      const auto grid8 = quantise8(f);
      table1Row(name.c_str(), "8-bit", grid8, {});
      table1Row(name.c_str(), "16-bit", quantise16(f), {});
      table1Row(name.c_str(), "8-bit 64-127", clamped(grid8, 64, 127), {});
      table1Row(name.c_str(), "8-bit var<=4", grid8, {4.0});
    }
}

// A pinhole camera on the volume's diagonal-ish view, 40° field of view, voxel space.
struct Camera {
  Vec3 eye, forward, right, up;
  double scale;
  volume::VolumeRay ray(int px, int py, int res) const {
    const double x = (2.0 * (px + 0.5) / res - 1.0) * scale,
                 y = (1.0 - 2.0 * (py + 0.5) / res) * scale;
    return {eye, glm::normalize(forward + right * x + up * y)};
  }
};
Camera cameraFor(glm::ivec3 size) {
  const Vec3 centre = Vec3(size - 1) * 0.5;
  const double radius = glm::length(Vec3(size - 1)) * 0.5;
  const Vec3 forward = glm::normalize(Vec3(-1.0, -0.6, -1.3));
  const Vec3 right = glm::normalize(glm::cross(forward, Vec3(0, 1, 0)));
  return {centre - forward * (radius / std::sin(glm::radians(20.0))), forward, right,
          glm::cross(right, forward), std::tan(glm::radians(20.0))};
}

// Seconds per frame (best of `frames`) and the number of hits of the last frame.
template <class Trace>
std::pair<double, long> renderFrames(const Camera& camera, int res, int threads, int frames,
                                     const Trace& trace) {
  tbb::task_arena arena(threads);
  double best = 1e300;
  long hits = 0;
  for (int frame = 0; frame < frames; ++frame) {
    std::atomic<long> count{0};
    const auto start = Clock::now();
    arena.execute([&] {
      tbb::parallel_for(tbb::blocked_range2d<int>(0, res, 16, 0, res, 16), [&](const auto& tile) {
        long local = 0;
        for (int y = tile.rows().begin(); y < tile.rows().end(); ++y)
          for (int x = tile.cols().begin(); x < tile.cols().end(); ++x)
            local += trace(camera.ray(x, y, res)).has_value();
        count += local;
      });
    });
    best = std::min(best, secondsSince(start));
    hits = count;
  }
  return {best, hits};
}

void table2(const Options& options) {
  const int n = options.renderSize, res = options.res;
  std::printf("\nTable 2: %d^2 frames of the isosurface of %d^3 8-bit fields (first hit only)\n\n",
              res, n);
  std::printf(
      "| field          | iso   | structure / data         | threads | hits   | Mrays/s | fps   | "
      "memory MB |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
  const double isos[] = {127.5, 127.5, 60.5, 127.5};  // ML, sphere, smoke, mixing
  int which = 0;
  for (VolumeField field : kVolumeFields) {
    const double iso = isos[which++];
    std::fprintf(stderr, "table 2: %s %d^3: generating and building\n",
                 volumeFieldName(field).c_str(), n);
    const auto grid = quantise8(makeVolumeField({field, glm::ivec3(n), 1}));
    const auto octree = volume::OctreeVolume<uint8_t>::build(grid);
    const volume::MacrocellGrid<uint8_t> macro(grid, 8);
    const Camera camera = cameraFor(grid.size);
    for (int threads : options.threads) {
      std::fprintf(stderr, "table 2: %s, %d thread(s)\n", volumeFieldName(field).c_str(), threads);
      const auto [tOct, hOct] = renderFrames(
          camera, res, threads, options.frames,
          [&](const volume::VolumeRay& r) { return volume::traceOctree(octree, r, iso); });
      const auto [tMac, hMac] =
          renderFrames(camera, res, threads, options.frames,
                       [&](const volume::VolumeRay& r) { return macro.trace(r, iso); });
      const double rays = double(res) * res;
      std::printf(
          "| %-14s | %5.1f | octree / octree volume   | %7d | %6ld | %7.2f | %5.2f | %9.2f |\n",
          volumeFieldName(field).c_str(), iso, threads, hOct, rays / tOct / 1e6, 1.0 / tOct,
          double(octree.bytes()) / 1e6);
      std::printf(
          "| %-14s | %5.1f | macrocell 8³ / raw array | %7d | %6ld | %7.2f | %5.2f | %9.2f |\n",
          volumeFieldName(field).c_str(), iso, threads, hMac, rays / tMac / 1e6, 1.0 / tMac,
          double(grid.bytes() + macro.bytes()) / 1e6);
      std::fflush(stdout);
    }
  }
}

}  // namespace
}  // namespace penumbra

int main(int argc, char** argv) {
  penumbra::Options options;
  try {
    for (int i = 1; i + 1 < argc; i += 2) {
      const std::string name = argv[i], value = argv[i + 1];
      if (name == "--sizes")
        options.sizes = penumbra::intList(value);
      else if (name == "--render-size")
        options.renderSize = std::stoi(value);
      else if (name == "--res")
        options.res = std::stoi(value);
      else if (name == "--threads")
        options.threads = penumbra::intList(value);
      else if (name == "--frames")
        options.frames = std::stoi(value);
      else
        throw std::invalid_argument("unknown option " + name);
    }
    if (argc % 2 == 0) throw std::invalid_argument("an option needs a value");
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra-volume-bench: %s\n", error.what());
    return 2;
  }
  penumbra::table1(options);
  penumbra::table2(options);
  return 0;
}
