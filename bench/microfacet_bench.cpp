// `penumbra-microfacet-bench [options]` (README "Benchmarks"): image error vs time of the DM
// estimator (MicrofacetShading::direct over the DM cell's exactly visible light pieces) against
// shadow rays over the whole light, same BSDF, direct light only, on bench/lib/glossy_scene.
// Prints markdown tables; writes the images, a plot and report.html into --out-dir.
#include "bench/microfacet_bench.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "bench/lib/glossy_direct.h"
#include "bench/lib/glossy_scene.h"
#include "core/engine/engine.h"
#include "core/engine/seconds_since.h"
#include "core/raycast/mesh_lookup.h"
#include "core/render/dm_visibility.h"
#include "imageio/image_encoding.h"

namespace penumbra::bench {
namespace {

std::vector<int> intList(const std::string& text) {
  std::vector<int> out;
  std::stringstream list(text);
  for (std::string item; std::getline(list, item, ',');) {
    size_t used = 0;
    out.push_back(std::stoi(item, &used));
    if (used != item.size() || out.back() < 1)
      throw std::invalid_argument("not a positive whole number: " + item);
  }
  if (out.empty()) throw std::invalid_argument("empty list");
  return out;
}

// The estimators being measured: a name, the estimator, its sample ladder, a seed base.
struct Contender {
  std::string name;
  DirectFn estimate;
  std::vector<int> samples;
  uint64_t seedBase = 0;
};

// Repeats one rung with fresh seeds until minSeconds are spent (at most 8 times) and appends
// the mean time and squared error; the reference's own noise variance is taken off the error.
void measureRung(const GlossyView& view, const Contender& c, int n,
                 const std::vector<float>& reference, double referenceVariance,
                 const MicrofacetBenchArgs& args, Ladder& ladder) {
  double seconds = 0, cpuSeconds = 0, mse = 0;
  int repeats = 0;
  do {
    const GlossyView::Run run = view.render(
        c.estimate, n, c.seedBase + 1000 * uint64_t(n) + uint64_t(repeats), args.threads);
    seconds += run.seconds;
    cpuSeconds += run.cpuSeconds;
    mse += meanSquaredError(run.linear, reference, view.glossyMask());
    ++repeats;
  } while (seconds < args.minSeconds && repeats < 8);
  seconds /= repeats;
  cpuSeconds /= repeats;
  mse /= repeats;
  const double mean = maskedMean(reference, view.glossyMask());
  ladder.points.push_back({n, seconds, std::sqrt(std::max(0.0, mse - referenceVariance)) / mean});
  ladder.cpuPoints.push_back({n, cpuSeconds, ladder.points.back().rms});
  ladder.rawRms.push_back(std::sqrt(mse) / mean);
  ladder.repeats.push_back(repeats);
  std::fprintf(stderr, "  %-11s %5d samples: %8.4f s (CPU %8.4f s), RMS %.4f%%\n", c.name.c_str(),
               n, seconds, cpuSeconds, 100 * ladder.points.back().rms);
}

// Both ladders, rung by rung in turn (DM rung k, then shadow-ray rung k), so a change in the
// shared machine's load falls on both rather than on whichever ran second.
std::pair<Ladder, Ladder> measureLadders(const GlossyView& view, const Contender& a,
                                         const Contender& b, const std::vector<float>& reference,
                                         double referenceVariance,
                                         const MicrofacetBenchArgs& args) {
  Ladder la, lb;
  la.name = a.name;
  lb.name = b.name;
  for (size_t k = 0; k < std::max(a.samples.size(), b.samples.size()); ++k) {
    if (k < a.samples.size())
      measureRung(view, a, a.samples[k], reference, referenceVariance, args, la);
    if (k < b.samples.size())
      measureRung(view, b, b.samples[k], reference, referenceVariance, args, lb);
  }
  return {la, lb};
}

// The diffuse pixels (DM mesh irradiance · albedo/π), for the pictures only.
std::vector<float> diffuseBase(const Scene& scene, const Mesh& mesh, const GlossyView& view) {
  const MeshLookup lookup(scene, mesh);
  std::vector<float> base(3 * size_t(view.width()) * size_t(view.height()), 0.0f);
  for (int j = 0; j < view.height(); ++j)
    for (int i = 0; i < view.width(); ++i) {
      const auto hit = view.primaryHit(i, j);
      if (!hit) continue;
      const auto e = lookup.irradiance(hit->faceIndex, hit->position);
      const Vec3 value =
          scene.albedo(scene.faces()[hit->faceIndex].id) / M_PI * (e ? *e : Vec3(0.0));
      const size_t p = size_t(j) * size_t(view.width()) + size_t(i);
      for (int c = 0; c < 3; ++c) base[3 * p + size_t(c)] = float(value[c]);
    }
  return base;
}

nlohmann::json ladderJson(const Ladder& ladder) {
  nlohmann::json rows = nlohmann::json::array();
  for (size_t k = 0; k < ladder.points.size(); ++k)
    rows.push_back({{"samples", ladder.points[k].samples},
                    {"seconds", ladder.points[k].seconds},
                    {"cpu_seconds", ladder.cpuPoints[k].seconds},
                    {"relative_rms", ladder.points[k].rms},
                    {"relative_rms_raw", ladder.rawRms[k]},
                    {"repeats", ladder.repeats[k]}});
  return rows;
}

std::string percent(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g %%", 100 * x);
  return buf;
}

// For each rung of `measured`, the time `other` needs for the same RMS (interpolated on its
// ladder) and the ratio DM time : shadow-ray time the other way up (shadow rays / DM), in wall and
// CPU seconds; markdown and JSON.
nlohmann::json matchErrors(const Ladder& measured, const Ladder& other, bool measuredIsDm,
                           std::string& markdown) {
  nlohmann::json rows = nlohmann::json::array();
  markdown += "\n| relative RMS | " + measured.name + " samples | " + measured.name +
              " s (CPU s) | " + other.name +
              " s to the same RMS (CPU s) | ratio shadow rays / DM, wall (CPU) |\n" +
              "|---|---|---|---|---|\n";
  for (size_t k = 0; k < measured.points.size(); ++k) {
    const LadderPoint& m = measured.points[k];
    const double mCpu = measured.cpuPoints[k].seconds;
    const auto wall = timeToReach(other.points, m.rms);
    const auto cpu = timeToReach(other.cpuPoints, m.rms);
    nlohmann::json row = {{"relative_rms", m.rms},
                          {"samples", m.samples},
                          {"seconds", m.seconds},
                          {"cpu_seconds", mCpu}};
    char line[320];
    if (wall && cpu) {
      const double ratio = measuredIsDm ? wall->seconds / m.seconds : m.seconds / wall->seconds;
      const double cpuRatio = measuredIsDm ? cpu->seconds / mCpu : mCpu / cpu->seconds;
      row["other_seconds"] = wall->seconds;
      row["other_cpu_seconds"] = cpu->seconds;
      row["ratio"] = ratio;
      row["cpu_ratio"] = cpuRatio;
      row["extrapolated"] = wall->extrapolated;
      row["first_rung"] = wall->firstRung;
      std::snprintf(line, sizeof line,
                    "| %s | %d | %.3f (%.3f) | %.3f (%.3f)%s | %.1f× (%.1f×) |\n",
                    percent(m.rms).c_str(), m.samples, m.seconds, mCpu, wall->seconds, cpu->seconds,
                    wall->extrapolated ? ", extrapolated"
                    : wall->firstRung  ? ", its first rung"
                                       : "",
                    ratio, cpuRatio);
    } else {
      std::snprintf(line, sizeof line, "| %s | %d | %.3f (%.3f) | — | — |\n",
                    percent(m.rms).c_str(), m.samples, m.seconds, mCpu);
    }
    markdown += line;
    rows.push_back(row);
  }
  return rows;
}

std::string ladderTable(const Ladder& dm, const Ladder& sr) {
  std::string out =
      "| samples | DM s (CPU s) | DM relative RMS | shadow rays s (CPU s) | shadow rays relative "
      "RMS |\n"
      "|---|---|---|---|---|\n";
  std::vector<int> all;
  for (const auto& p : dm.points) all.push_back(p.samples);
  for (const auto& p : sr.points) all.push_back(p.samples);
  std::sort(all.begin(), all.end());
  all.erase(std::unique(all.begin(), all.end()), all.end());
  auto cells = [](const Ladder& l, int n) {
    for (size_t k = 0; k < l.points.size(); ++k)
      if (l.points[k].samples == n) {
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.3f (%.3f) | %s", l.points[k].seconds,
                      l.cpuPoints[k].seconds, percent(l.points[k].rms).c_str());
        return std::string(buf);
      }
    return std::string("— | —");
  };
  for (int n : all)
    out += "| " + std::to_string(n) + " | " + cells(dm, n) + " | " + cells(sr, n) + " |\n";
  return out;
}

// The reference: shadow rays only (independent of the DM), the mean of two independent images;
// their difference measures its own noise (variance of the mean = E[(A - B)²] / 4).
struct Reference {
  std::vector<float> image;
  double variance = 0, mean = 0, seconds = 0;
};

Reference measureReference(const GlossyView& view, const DirectFn& shadowRays,
                           const MicrofacetBenchArgs& args) {
  const auto start = std::chrono::steady_clock::now();
  const auto a =
      view.render(shadowRays, args.referenceSamples, args.seed * 7919 + 1, args.referenceThreads);
  const auto b =
      view.render(shadowRays, args.referenceSamples, args.seed * 7919 + 2, args.referenceThreads);
  Reference r;
  r.seconds = secondsSince(start);
  r.image.resize(a.linear.size());
  for (size_t k = 0; k < r.image.size(); ++k) r.image[k] = 0.5f * (a.linear[k] + b.linear[k]);
  r.variance = meanSquaredError(a.linear, b.linear, view.glossyMask()) / 4;
  r.mean = maskedMean(r.image, view.glossyMask());
  std::fprintf(stderr, "%zu microfacet pixels; reference: %.1f s, relative noise %.4f%%\n",
               view.glossyPixels(), r.seconds, 100 * std::sqrt(r.variance) / r.mean);
  return r;
}

}  // namespace

MicrofacetBenchArgs parseMicrofacetArgs(int argc, char** argv) {
  MicrofacetBenchArgs a;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    if (i + 1 >= argc) throw std::invalid_argument(name + " needs a value");
    const std::string value = argv[++i];
    try {
      if (name == "--width")
        a.width = std::stoi(value);
      else if (name == "--height")
        a.height = std::stoi(value);
      else if (name == "--dm-samples")
        a.dmSamples = intList(value);
      else if (name == "--sr-samples")
        a.srSamples = intList(value);
      else if (name == "--reference-samples")
        a.referenceSamples = std::stoi(value);
      else if (name == "--roughness")
        a.roughness = std::stod(value);
      else if (name == "--scattering") {
        if (value != "multiple" && value != "single")
          throw std::invalid_argument("multiple or single");
        a.singleScattering = value == "single";
      } else if (name == "--threads")
        a.threads = std::stoi(value);
      else if (name == "--reference-threads")
        a.referenceThreads = std::stoi(value);
      else if (name == "--min-seconds")
        a.minSeconds = std::stod(value);
      else if (name == "--image-samples")
        a.imageSamples = std::stoi(value);
      else if (name == "--seed")
        a.seed = std::stoull(value);
      else if (name == "--out-dir")
        a.outDir = value;
      else
        throw std::invalid_argument("unknown option");
    } catch (const std::logic_error& error) {
      throw std::invalid_argument(name + " '" + value + "': " + error.what());
    }
  }
  if (a.width < 1 || a.height < 1 || a.width > 4096 || a.height > 4096)
    throw std::invalid_argument("size 1..4096");
  if (a.referenceSamples < 1 || a.imageSamples < 1 || !(a.roughness > 0))
    throw std::invalid_argument("bad value");
  return a;
}

int runMicrofacetBench(const MicrofacetBenchArgs& args) {
  imageio::loadImageModule();  // fail before the work, not after
  std::filesystem::create_directories(args.outDir);
  const Scene scene = makeGlossyScene({args.roughness, args.singleScattering});
  auto start = std::chrono::steady_clock::now();
  EngineSettings engineSettings;
  engineSettings.threads = args.threads;
  Engine engine(scene, engineSettings);
  const Mesh mesh = engine.mesh();
  const double engineSeconds = secondsSince(start);

  const RayScene rays(scene);
  const MicrofacetShading shading(scene, rays, backprojectedPieces(scene, dmOccluderLists(engine)),
                                  [](uint32_t, const Vec3&, bool) { return Vec3(0.0); });
  const ShadowRayDirect shadowRays(scene, rays);
  const GlossyView view(scene, rays, *scene.camera(), args.width, args.height,
                        [&](uint32_t f) { return shading.isMicrofacet(f); });
  const DirectFn dm = [&](uint32_t f, const Vec3& p, const Vec3& wo, int n, bsdf::Rng& rng) {
    return shading.direct(f, p, wo, n, rng);
  };
  const DirectFn sr = [&](uint32_t f, const Vec3& p, const Vec3& wo, int n, bsdf::Rng& rng) {
    return shadowRays(f, p, wo, n, rng);
  };

  const Reference reference = measureReference(view, sr, args);
  const auto [dmLadder, srLadder] =
      measureLadders(view, {"DM", dm, args.dmSamples, args.seed * 31},
                     {"shadow rays", sr, args.srSamples, args.seed * 37}, reference.image,
                     reference.variance, args);

  char header[320];
  std::snprintf(
      header, sizeof header,
      "Direct light, DM pieces vs shadow rays: GGX conductor α %g, %s scattering, %dx%d (%zu "
      "microfacet "
      "pixels), %d thread(s); reference 2 x %d shadow-ray samples, relative noise %.3g %%\n\n",
      args.roughness, args.singleScattering ? "single" : "multiple", args.width, args.height,
      view.glossyPixels(), args.threads, args.referenceSamples,
      100 * std::sqrt(reference.variance) / reference.mean);
  std::printf("%s", header);
  std::string markdown = ladderTable(dmLadder, srLadder);
  const nlohmann::json matched = {
      {"dm_rungs", matchErrors(dmLadder, srLadder, true, markdown)},
      {"shadow_ray_rungs", matchErrors(srLadder, dmLadder, false, markdown)}};
  std::printf("%s", markdown.c_str());

  BenchImages images{
      args.width,
      args.height,
      view.glossyMask(),
      diffuseBase(scene, mesh, view),
      reference.image,
      view.render(dm, args.imageSamples, args.seed * 41, args.referenceThreads).linear,
      view.render(sr, args.imageSamples, args.seed * 43, args.referenceThreads).linear,
      args.imageSamples};
  const nlohmann::json numbers = {
      {"scene",
       {{"roughness", args.roughness},
        {"scattering", args.singleScattering ? "single" : "multiple"},
        {"faces", scene.faces().size()}}},
      {"width", args.width},
      {"height", args.height},
      {"glossy_pixels", view.glossyPixels()},
      {"threads", args.threads},
      {"engine_build_and_mesh_seconds", engineSeconds},
      {"reference",
       {{"samples_per_image", args.referenceSamples},
        {"images", 2},
        {"seconds", reference.seconds},
        {"relative_noise", std::sqrt(reference.variance) / reference.mean}}},
      {"dm", ladderJson(dmLadder)},
      {"shadow_rays", ladderJson(srLadder)},
      {"matched", matched}};
  writeMicrofacetReport(args, images, dmLadder, srLadder, numbers, markdown);
  std::printf("wrote %s/report.html\n", args.outDir.c_str());
  return 0;
}

}  // namespace penumbra::bench

int main(int argc, char** argv) {
  try {
    return penumbra::bench::runMicrofacetBench(penumbra::bench::parseMicrofacetArgs(argc, argv));
  } catch (const std::invalid_argument& error) {
    std::fprintf(
        stderr,
        "penumbra-microfacet-bench: %s\nusage: penumbra-microfacet-bench [--width W] [--height H] "
        "[--dm-samples 1,4,..] [--sr-samples 1,4,..]\n  [--reference-samples N] [--roughness A] "
        "[--scattering multiple|single] [--threads T] [--reference-threads T]\n  [--min-seconds S] "
        "[--image-samples N] [--seed S] [--out-dir DIR]\n",
        error.what());
    return 2;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "penumbra-microfacet-bench: %s\n", error.what());
    return 1;
  }
}
