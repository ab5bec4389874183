// The microfacet bench's report: PNGs through the project's image encoding (OpenImageIO), the
// error-vs-time plot as SVG, report.html and the JSON (bench/microfacet_bench.h).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "bench/microfacet_bench.h"
#include "bench/report/html_page.h"
#include "bench/report/svg_charts.h"
#include "imageio/image_encoding.h"

namespace penumbra::bench {
namespace {

// One exposure for every picture: 1 / the 99th percentile of the reference's largest channel.
double exposureOf(const std::vector<float>& linear) {
  std::vector<float> values;
  for (size_t p = 0; 3 * p < linear.size(); ++p)
    if (float v = std::max({linear[3 * p], linear[3 * p + 1], linear[3 * p + 2]}); v > 0)
      values.push_back(v);
  if (values.empty()) return 1;
  const size_t k = std::min(values.size() - 1, size_t(0.99 * double(values.size())));
  std::nth_element(values.begin(), values.begin() + long(k), values.end());
  return values[k] > 0 ? 1.0 / values[k] : 1.0;
}

RenderedImage imageOf(int width, int height, std::vector<float> linear, double exposure) {
  RenderedImage image;
  image.width = width;
  image.height = height;
  image.exposure = exposure;
  image.srgb.resize(linear.size());
  for (size_t k = 0; k < linear.size(); ++k)
    image.srgb[k] = uint8_t(std::lround(255 * srgbEncode(exposure * linear[k])));
  image.linear = std::move(linear);
  return image;
}

// The estimator's microfacet pixels over the shared diffuse ones.
std::vector<float> composite(const BenchImages& images, const std::vector<float>& glossy) {
  std::vector<float> out = images.base;
  for (size_t p = 0; p < images.mask.size(); ++p)
    if (images.mask[p])
      for (size_t c = 0; c < 3; ++c) out[3 * p + c] = glossy[3 * p + c];
  return out;
}

// Tiles (same size, sRGB bytes) in a grid `columns` wide, 4 white pixels between them.
RenderedImage grid(const std::vector<const RenderedImage*>& tiles, int columns) {
  constexpr int kGap = 4;
  const int w = tiles[0]->width, h = tiles[0]->height,
            rows = int((tiles.size() + size_t(columns) - 1) / size_t(columns));
  RenderedImage out;
  out.width = columns * w + (columns - 1) * kGap;
  out.height = rows * h + (rows - 1) * kGap;
  out.srgb.assign(3 * size_t(out.width) * size_t(out.height), 255);
  out.linear.assign(out.srgb.size(), 1.0f);
  for (size_t t = 0; t < tiles.size(); ++t) {
    const int x0 = int(t % size_t(columns)) * (w + kGap),
              y0 = int(t / size_t(columns)) * (h + kGap);
    for (int j = 0; j < h; ++j)
      std::copy_n(tiles[t]->srgb.begin() + 3 * long(j) * w, 3 * w,
                  out.srgb.begin() + 3 * (long(y0 + j) * out.width + x0));
  }
  return out;
}

// The middle half of an image (half its width and height, centred a little below the middle,
// where the box's penumbra lies): the small comparison for the README.
RenderedImage middle(const RenderedImage& image) {
  RenderedImage out;
  out.width = std::max(1, image.width / 2);
  out.height = std::max(1, image.height / 2);
  const int x0 = image.width / 4, y0 = std::min(image.height - out.height, image.height * 3 / 10);
  out.srgb.resize(3 * size_t(out.width) * size_t(out.height));
  out.linear.assign(out.srgb.size(), 0.0f);
  for (int j = 0; j < out.height; ++j)
    std::copy_n(image.srgb.begin() + 3 * (long(y0 + j) * image.width + x0), 3 * out.width,
                out.srgb.begin() + 3 * long(j) * out.width);
  return out;
}

void requireFinite(const std::vector<float>& values, const char* what) {
  for (float v : values)
    if (!std::isfinite(v))
      throw std::runtime_error(std::string("non-finite value in the ") + what + " image");
}

std::string plotSvg(const Ladder& dm, const Ladder& sr) {
  Plot plot;
  plot.title = "Relative RMS error vs time (direct light, microfacet pixels)";
  plot.xLabel = "seconds per image";
  plot.yLabel = "relative RMS error";
  plot.logX = plot.logY = true;
  for (const Ladder* l : {&dm, &sr}) {
    Series series;
    series.name = l->name + " (samples " + std::to_string(l->points.front().samples) + "…" +
                  std::to_string(l->points.back().samples) + ")";
    for (const LadderPoint& p : l->points) series.points.emplace_back(p.seconds, p.rms);
    plot.series.push_back(series);
  }
  plot.legendWidth = 230;
  return svgPlot(plot);
}

// Markdown table rows (| a | b |) to an HTML table.
std::string htmlTables(const std::string& markdown) {
  std::string out, line;
  bool open = false, header = false;
  for (size_t at = 0; at <= markdown.size(); ++at) {
    if (at < markdown.size() && markdown[at] != '\n') {
      line += markdown[at];
      continue;
    }
    if (line.rfind("|---", 0) == 0) {
      line.clear();
      continue;
    }
    if (line.rfind("|", 0) == 0) {
      if (!open) out += "<table>";
      header = !open;
      open = true;
      out += "<tr>";
      size_t from = 1;
      for (size_t bar; (bar = line.find('|', from)) != std::string::npos; from = bar + 1)
        out += (header ? "<th>" : "<td>") + escapeHtml(line.substr(from, bar - from)) +
               (header ? "</th>" : "</td>");
      out += "</tr>\n";
    } else if (open) {
      out += "</table>\n";
      open = false;
    }
    line.clear();
  }
  return open ? out + "</table>\n" : out;
}

// What was measured and how, above the tables.
std::string introHtml(const MicrofacetBenchArgs& args) {
  return "<p>Direct light on the glossy floor (GGX conductor, α " + shortNumber(args.roughness) +
         ", " + (args.singleScattering ? "single" : "multiple") +
         " scattering) under one rectangular light, a box casting a wide penumbra. <b>DM</b>: "
         "MicrofacetShading::direct over the light pieces the DM cell's occluder list leaves "
         "visible (a "
         "Backprojection; the light's samples split over the pieces by area, no shadow rays). "
         "<b>Shadow "
         "rays</b>: the same BSDF and stratification over the whole light, one Embree shadow ray "
         "per sample. "
         "Both at " +
         std::to_string(args.threads) +
         " thread(s), DM and shadow-ray rungs in turn; times of whole images (primary rays "
         "included). The "
         "reference is the mean of two shadow-ray images of " +
         std::to_string(args.referenceSamples) +
         " samples per pixel; its noise is taken off the squared errors. RMS over the microfacet "
         "pixels, "
         "relative to their mean.</p>\n";
}

}  // namespace

void writeMicrofacetReport(const MicrofacetBenchArgs& args, const BenchImages& images,
                           const Ladder& dm, const Ladder& shadowRays,
                           const nlohmann::json& numbers, const std::string& markdown) {
  requireFinite(images.dm, "DM");
  requireFinite(images.shadowRays, "shadow-ray");
  requireFinite(images.reference, "reference");
  for (const Ladder* l : {&dm, &shadowRays})
    for (const LadderPoint& p : l->points)
      if (!std::isfinite(p.rms) || !std::isfinite(p.seconds))
        throw std::runtime_error("non-finite error or time");

  const std::string dir = args.outDir + "/";
  const std::vector<float> referenceImage = composite(images, images.reference);
  const double exposure = exposureOf(referenceImage);
  const RenderedImage dmImage =
      imageOf(images.width, images.height, composite(images, images.dm), exposure);
  const RenderedImage srImage =
      imageOf(images.width, images.height, composite(images, images.shadowRays), exposure);
  const RenderedImage refImage = imageOf(images.width, images.height, referenceImage, exposure);
  // Heat maps: white at 4× the shadow-ray image's mean absolute error.
  double meanAbs = 0, count = 0;
  for (size_t p = 0; p < images.mask.size(); ++p)
    if (images.mask[p])
      for (size_t c = 0; c < 3; ++c, ++count)
        meanAbs += std::abs(images.shadowRays[3 * p + c] - images.reference[3 * p + c]);
  const double scale = 4 * (count > 0 ? meanAbs / count : 1.0);
  RenderedImage dmHeat = imageOf(images.width, images.height, images.dm, 1.0);
  RenderedImage srHeat = imageOf(images.width, images.height, images.shadowRays, 1.0);
  dmHeat.srgb = errorHeatMap(images.dm, images.reference, images.mask, scale);
  srHeat.srgb = errorHeatMap(images.shadowRays, images.reference, images.mask, scale);

  const std::string n = std::to_string(images.samples);
  imageio::writeImageFile(dmImage, dir + "dm.png");
  imageio::writeImageFile(srImage, dir + "shadow_rays.png");
  imageio::writeImageFile(refImage, dir + "reference.png");
  imageio::writeImageFile(dmHeat, dir + "dm_error.png");
  imageio::writeImageFile(srHeat, dir + "shadow_rays_error.png");
  imageio::writeImageFile(grid({&dmImage, &srImage, &refImage, &dmHeat, &srHeat}, 3),
                         dir + "comparison.png");
  const RenderedImage small[] = {middle(dmImage), middle(srImage), middle(refImage), middle(dmHeat),
                                 middle(srHeat)};
  imageio::writeImageFile(grid({&small[0], &small[1], &small[2], &small[3], &small[4]}, 3),
                         dir + "comparison_middle.png");
  const std::string svg = plotSvg(dm, shadowRays);
  std::ofstream(dir + "error_vs_time.svg")
      << svg.substr(svg.find("<svg"), svg.rfind("</svg>") + 6 - svg.find("<svg")) << "\n";
  std::ofstream(dir + "microfacet.json") << numbers.dump(2) << "\n";

  const std::string body =
      introHtml(args) + htmlTables(markdown) + svg + "<h2>Images at " + n +
      " samples</h2>\n<p>Top: DM, shadow rays, reference (same exposure). Bottom: |error| "
      "of DM and shadow rays (black 0, white ≥ 4× the shadow-ray image's mean |error|).</p>\n"
      "<img src='comparison.png' alt='comparison'/>\n";
  std::ofstream(dir + "report.html")
      << htmlPage("Microfacet direct light: DM pieces vs shadow rays", body, numbers);
  if (!std::ofstream(dir + "report.html", std::ios::app).good())
    throw std::runtime_error("cannot write " + dir);
}

}  // namespace penumbra::bench
