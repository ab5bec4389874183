// `penumbra-gi-bench [--scene FILE] [--threads N] [--quick] [--html OUT] [--json OUT]` (README
// "Global illumination"): sensor GI (core/gi) on a scene's camera view — seed 001's three metrics
// (time per sensor vs image size; vs sensor-map size; sensors needed vs sensor-map size), each
// run's RMS relative error of the indirect irradiance against the one-bounce path tracer
// (bench/lib/gi_path_tracer.h) at random surface pixels, and the path tracer's time to the same
// error. One bounce on both sides.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include <nlohmann/json.hpp>

#include "bench/lib/gi_path_tracer.h"
#include "bench/report/html_page.h"
#include "bench/report/svg_charts.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/gi/sensor_gi.h"
#include "core/gi/view_gbuffer.h"
#include "core/raycast/camera_projection.h"
#include "protocol/scene_json.h"

using namespace penumbra;
using nlohmann::json;

namespace {

double largest(const Vec3& v) { return std::max({v.x, v.y, v.z}); }

struct Setup {
  Scene scene;
  Mesh mesh;
  RayScene rays{scene};
  MeshLookup direct{scene, mesh};
  explicit Setup(const std::string& path) : scene(protocol::loadSceneFile(path)), mesh(Engine(scene).mesh()) {}
};

gi::GBuffer viewOf(const Setup& s, int size) {
  return gi::viewGBuffer(s.rays, s.scene.camera().value_or(defaultCamera(s.scene.bounds())), size, size, Parallel(0));
}

// Random surface pixels of a view and the path tracer's indirect irradiance there.
struct Reference {
  std::vector<size_t> pixels;
  std::vector<Vec3> values;
};

Reference referenceOf(const Setup& s, const gi::GBuffer& g, int count, int samples, uint64_t seed) {
  Reference r;
  std::mt19937_64 rng(seed);
  while (int(r.pixels.size()) < count) {
    const size_t p = rng() % g.face.size();
    if (g.face[p] < 0) continue;
    const Vec3 n = s.scene.faces()[size_t(g.face[p])].plane.normal;
    const Vec3 e = bench::pathTracedIndirect(s.scene, s.rays, s.direct, g.position[p], n, samples, rng).mean;
    if (largest(e) <= 0) continue;  // no bounced light there: no relative error
    r.pixels.push_back(p);
    r.values.push_back(e);
  }
  return r;
}

double rmsError(const Reference& r, const std::function<Vec3(size_t k)>& estimate) {
  double squares = 0;
  for (size_t k = 0; k < r.pixels.size(); ++k) {
    const double e = largest(glm::abs(estimate(k) - r.values[k])) / largest(r.values[k]);
    squares += e * e;
  }
  return std::sqrt(squares / double(r.pixels.size()));
}

json sensorRun(const Setup& s, const gi::GBuffer& g, int sensorSize, int threads, const Reference* ref,
               double threshold = gi::PlacementSettings{}.threshold) {
  gi::GiSettings settings;
  settings.sensorSize = sensorSize;
  settings.placement.threshold = threshold;
  const gi::IndirectImage image = gi::indirectImage(s.scene, s.rays, s.mesh, g, settings, Parallel(threads));
  json row = {{"size", g.width}, {"sensor_size", sensorSize}, {"threshold", threshold},
              {"sensors", image.placement.sensors},
              {"seconds", image.seconds},
              {"ms_per_sensor", 1e3 * image.seconds / double(std::max<size_t>(1, image.placement.sensors))}};
  if (ref) row["rms_error"] = rmsError(*ref, [&](size_t k) { return image.irradiance[ref->pixels[k]]; });
  std::fprintf(stderr, "  %d² sensors %d², threshold %.2f: %zu sensors, %.2f s\n", g.width, sensorSize, threshold,
               image.placement.sensors, image.seconds);
  return row;
}

// The path tracer at n paths per pixel: RMS error at the reference pixels, and the time a whole
// image would take (the reference pixels' time per path × surface pixels × n).
json pathTracerRun(const Setup& s, const gi::GBuffer& g, const Reference& ref, int n, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<Vec3> values;
  const auto start = std::chrono::steady_clock::now();
  for (size_t k = 0; k < ref.pixels.size(); ++k) {
    const size_t p = ref.pixels[k];
    const Vec3 normal = s.scene.faces()[size_t(g.face[p])].plane.normal;
    values.push_back(bench::pathTracedIndirect(s.scene, s.rays, s.direct, g.position[p], normal, n, rng).mean);
  }
  const double perPixel = secondsSince(start) / double(ref.pixels.size());
  size_t surface = 0;
  for (int32_t f : g.face) surface += f >= 0;
  return {{"paths", n}, {"rms_error", rmsError(ref, [&](size_t k) { return values[k]; })},
          {"seconds", perPixel * double(surface)}};
}

// The path tracer's time at error e, interpolated log–log between its rungs (null outside).
json timeAtError(const json& ladder, double e) {
  for (size_t k = 1; k < ladder.size(); ++k) {
    const double e0 = ladder[k - 1]["rms_error"], e1 = ladder[k]["rms_error"];
    if ((e0 - e) * (e1 - e) > 0) continue;
    const double f = std::log(e / e0) / std::log(e1 / e0);
    return std::exp(std::log(double(ladder[k - 1]["seconds"])) +
                    f * (std::log(double(ladder[k]["seconds"])) - std::log(double(ladder[k - 1]["seconds"]))));
  }
  return nullptr;
}

std::string report(const json& result) {
  auto series = [&](const char* key, const char* x, const char* y) {
    std::vector<bench::Series> out;
    bench::Series line{key, {}};
    for (const json& row : result[key]) line.points.push_back({double(row[x]), double(row[y])});
    out.push_back(line);
    return out;
  };
  std::string body = "<p>Sensor GI (seed 001) on " + bench::escapeHtml(result["scene"].get<std::string>()) +
                     ", " + std::to_string(int(result["threads"])) + " thread(s). One bounce.</p>";
  body += bench::svgPlot({"Time per sensor vs image size (sensor 32²)", "image side (px)", "ms per sensor", false,
                          false, series("by_resolution", "size", "ms_per_sensor")});
  body += bench::svgPlot({"Time per sensor vs sensor-map size", "sensor map side", "ms per sensor", true, true,
                          series("by_sensor_size", "sensor_size", "ms_per_sensor")});
  body += bench::svgPlot({"Sensors needed vs sensor-map size", "sensor map side", "sensors", true, false,
                          series("by_sensor_size", "sensor_size", "sensors")});
  bench::Plot errors{"RMS relative error vs time", "seconds (whole image)", "RMS relative error", true, true, {}};
  bench::Series sensors{"sensors (by map size)", {}}, paths{"path tracer (by paths per pixel)", {}};
  for (const json& row : result["by_sensor_size"]) sensors.points.push_back({row["seconds"], row["rms_error"]});
  for (const json& row : result["path_tracer"]) paths.points.push_back({row["seconds"], row["rms_error"]});
  errors.series = {sensors, paths};
  body += bench::svgPlot(errors);
  return bench::htmlPage("Sensor GI benchmark", body, result);
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = PENUMBRA_SOURCE_DIR "/scenes/cornell.scene.json", html, jsonOut;
  int threads = 1;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    if (a == "--scene") scenePath = value();
    else if (a == "--threads") threads = std::stoi(value());
    else if (a == "--html") html = value();
    else if (a == "--json") jsonOut = value();
    else if (a == "--quick") quick = true;
    else {
      std::fprintf(stderr, "usage: penumbra-gi-bench [--scene FILE] [--threads N] [--quick] [--html OUT] [--json OUT]\n");
      return 2;
    }
  }
  const Setup s(scenePath);
  const std::vector<int> sizes = quick ? std::vector<int>{24, 32} : std::vector<int>{64, 128, 192, 256};
  const std::vector<int> sensorSizes = quick ? std::vector<int>{4, 8} : std::vector<int>{8, 16, 32, 64};
  const int view = quick ? 32 : 128;
  json result = {{"scene", scenePath}, {"threads", threads}, {"view", view}};
  std::fprintf(stderr, "time per sensor vs image size\n");
  for (int size : sizes) result["by_resolution"].push_back(sensorRun(s, viewOf(s, size), 32, threads, nullptr));
  const gi::GBuffer g = viewOf(s, view);
  std::fprintf(stderr, "reference: path tracer at %d pixels\n", quick ? 10 : 150);
  const Reference ref = referenceOf(s, g, quick ? 10 : 150, quick ? 1024 : 65536, 7);
  for (int n : sensorSizes) result["by_sensor_size"].push_back(sensorRun(s, g, n, threads, &ref));
  for (double threshold : quick ? std::vector<double>{0.2} : std::vector<double>{0.1, 0.2, 0.4})
    result["by_threshold"].push_back(sensorRun(s, g, 32, threads, &ref, threshold));
  for (int n : quick ? std::vector<int>{16, 64} : std::vector<int>{16, 64, 256, 1024, 4096, 16384})
    result["path_tracer"].push_back(pathTracerRun(s, g, ref, n, 100 + uint64_t(n)));
  // The figure: both methods' time to 3% RMS error (log–log between rungs).
  result["at_3_percent"] = {{"path_tracer_seconds", timeAtError(result["path_tracer"], 0.03)},
                            {"sensors_seconds", timeAtError(result["by_sensor_size"], 0.03)}};
  if (!result["at_3_percent"]["path_tracer_seconds"].is_null() && !result["at_3_percent"]["sensors_seconds"].is_null())
    result["at_3_percent"]["speedup"] = double(result["at_3_percent"]["path_tracer_seconds"]) /
                                        double(result["at_3_percent"]["sensors_seconds"]);
  for (const char* key : {"by_sensor_size", "by_threshold"})
  for (json& row : result[key]) {
    row["path_tracer_seconds_at_same_error"] = timeAtError(result["path_tracer"], row["rms_error"]);
    if (!row["path_tracer_seconds_at_same_error"].is_null())
      row["speedup"] = double(row["path_tracer_seconds_at_same_error"]) / double(row["seconds"]);
  }
  std::printf("| image | sensor map | threshold | sensors | seconds | ms per sensor | RMS error | path tracer s at that error | speed-up |\n|---|---|---|---|---|---|---|---|---|\n");
  for (const char* key : {"by_resolution", "by_sensor_size", "by_threshold"})
    for (const json& row : result[key])
      std::printf("| %d² | %d² | %.2f | %zu | %.2f | %.3f | %s | %s | %s |\n", int(row["size"]), int(row["sensor_size"]),
                  double(row["threshold"]),
                  size_t(row["sensors"]), double(row["seconds"]), double(row["ms_per_sensor"]),
                  row.contains("rms_error") ? bench::shortNumber(row["rms_error"]).c_str() : "",
                  row.contains("path_tracer_seconds_at_same_error") && !row["path_tracer_seconds_at_same_error"].is_null()
                      ? bench::shortNumber(row["path_tracer_seconds_at_same_error"]).c_str() : "",
                  row.contains("speedup") ? bench::shortNumber(row["speedup"]).c_str() : "");
  std::printf("\n| path tracer paths per pixel | RMS error | seconds (whole %d² image) |\n|---|---|---|\n", view);
  for (const json& row : result["path_tracer"])
    std::printf("| %d | %.4f | %.2f |\n", int(row["paths"]), double(row["rms_error"]), double(row["seconds"]));
  std::printf("\nTo 3%% RMS error: %s\n", result["at_3_percent"].dump().c_str());
  if (!jsonOut.empty()) std::ofstream(jsonOut) << result.dump(2) << "\n";
  if (!html.empty()) std::ofstream(html) << report(result);
  return 0;
}
