// `penumbra-bsdf-bench [--walks N] [--seed S]`: energies and lobes of the microfacet BSDF
// (core/bsdf) for the supplement's configurations (seed 004, Figs. 4-15): per bounce order, the
// reflected / transmitted energy E_r / E_t of the height-sampling reference (Heitz et al. 2016),
// of the position-free walk (height-correlated and -uncorrelated) and of single scattering,
// and the relative L1 distance of each order's lobe to the reference (with its noise level).
#include <cstdio>
#include <stdexcept>
#include <string>

#include "bench/lib/bsdf_lobes.h"

using namespace penumbra;
using namespace penumbra::bench;

namespace {

void printRow(const char* model, const Lobes& l) {
  double er = 0, et = 0;
  std::printf("  %-14s", model);
  for (int o = 0; o < Lobes::kOrders; ++o) {
    std::printf(" %6.4f/%6.4f", l.reflected(o), l.transmitted(o));
    er += l.reflected(o);
    et += l.transmitted(o);
  }
  std::printf("  | %6.4f/%6.4f\n", er, et);
}

void printL1(const char* model, const Lobes& l, const Lobes& ref) {
  std::printf("  %-14s", model);
  for (int o = 0; o < Lobes::kOrders; ++o) std::printf("   %5.3f (%5.3f)", relativeL1(l, ref, o), relativeL1Noise(ref, o));
  std::printf("\n");
}

std::string orders(const Lobes& l) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f/%.3f/%.3f", l.reflected(0) + l.transmitted(0),
                l.reflected(1) + l.transmitted(1), l.reflected(2) + l.transmitted(2));
  return buf;
}

std::string split(const Lobes& l) {
  double er = 0, et = 0;
  for (int o = 0; o < Lobes::kOrders; ++o) {
    er += l.reflected(o);
    et += l.transmitted(o);
  }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3f/%.3f", er, et);
  return buf;
}

double singleEnergy(const LobeConfig& c, int walks, uint64_t seed) {
  const bsdf::WalkParams single = walkParams(c, bsdf::HeightModel::Correlated, true);
  bsdf::Rng rng(seed);
  double e = 0;
  for (int i = 0; i < walks; ++i)
    if (const auto x = bsdf::sampleWalk(single, {std::sin(c.theta), 0.0, std::cos(c.theta)}, rng)) e += x->weight.x / walks;
  return e;
}

void printMarkdownRow(const LobeConfig& c, const Lobes& ref, const Lobes& corr, const Lobes& unc, int walks,
                      uint64_t seed) {
  static const char* facets[] = {"rough diffuse", "conductor", "dielectric"};
  std::printf("| %s | (%.2g, %.2g) | %.1f | %s | %s | %s | %.3f | %s | %s | %s | %.3f, %.3f | %.3f, %.3f | %.3f, %.3f |\n",
              facets[int(c.facets)], c.alphaX, c.alphaY, c.theta, orders(ref).c_str(), orders(corr).c_str(),
              orders(unc).c_str(), singleEnergy(c, walks, seed + 3), split(ref).c_str(), split(corr).c_str(),
              split(unc).c_str(), relativeL1(corr, ref, 0), relativeL1(corr, ref, 1), relativeL1(unc, ref, 0),
              relativeL1(unc, ref, 1), relativeL1Noise(ref, 0), relativeL1Noise(ref, 1));
}

}  // namespace

int main(int argc, char** argv) {
  int walks = 200000;
  uint64_t seed = 1;
  bool markdown = false;
  for (int i = 1; i < argc; ++i) {
    const std::string name = argv[i];
    const bool hasValue = i + 1 < argc;
    if (name == "--markdown") {
      markdown = true;
    } else if (name == "--walks" && hasValue) {
      walks = std::stoi(argv[++i]);
    } else if (name == "--seed" && hasValue) {
      seed = std::stoull(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: penumbra-bsdf-bench [--walks N] [--seed S] [--markdown]\n");
      return 2;
    }
  }
  if (markdown) {
    std::printf("| facets | alpha | theta | E per order 1/2/3+: Heitz 2016 | corr. | uncorr. | single | E_r/E_t Heitz | corr. | uncorr. | rel. L1 order 1, 2 corr. | uncorr. | noise |\n");
    std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  } else {
  std::printf("GGX; conductor F = 1, rough diffuse albedo 1, dielectric ior 1.5; %d walks each\n", walks);
  std::printf("E_r/E_t per bounce order: 1, 2, 3+ | total\n");
  }
  const bsdf::Facets facets[] = {bsdf::Facets::RoughDiffuse, bsdf::Facets::Conductor, bsdf::Facets::Dielectric};
  const double alphas[][2] = {{0.25, 0.25}, {0.5, 0.5}, {1.0, 1.0}, {1.0, 0.1}};
  for (bsdf::Facets f : facets) {
    for (const auto& a : alphas) {
      for (double theta : {0.0, 0.5, 1.0, 1.5}) {
        const LobeConfig c{f, a[0], a[1], theta};
        const Lobes ref = heitzLobes(c, walks, seed);
        const Lobes corr = walkLobes(c, bsdf::HeightModel::Correlated, walks, seed + 1);
        const Lobes unc = walkLobes(c, bsdf::HeightModel::Uncorrelated, walks, seed + 2);
        if (markdown) {
          printMarkdownRow(c, ref, corr, unc, walks, seed);
          continue;
        }
        std::printf("%s\n", c.name().c_str());
        printRow("Heitz 2016", ref);
        printRow("ours corr.", corr);
        printRow("ours uncorr.", unc);
        // Single scattering: the first bounce with its escape probability as weight.
        bsdf::WalkParams single = walkParams(c, bsdf::HeightModel::Correlated, true);
        bsdf::Rng rng(seed + 3);
        double er = 0, et = 0;
        for (int i = 0; i < walks; ++i) {
          const auto e = bsdf::sampleWalk(single, {std::sin(theta), 0.0, std::cos(theta)}, rng);
          if (e) (e->direction.z > 0 ? er : et) += e->weight.x / walks;
        }
        std::printf("  %-14s %6.4f/%6.4f\n", "single (corr.)", er, et);
        std::printf("  relative L1 to Heitz per order (noise):\n");
        printL1("ours corr.", corr, ref);
        printL1("ours uncorr.", unc, ref);
      }
    }
  }
  return 0;
}
