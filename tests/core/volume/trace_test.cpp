// Ray–isosurface hits of the octree traversal against an independent evaluation that shares
// no code with core/volume (the dense array, trilinear interpolation written again, a march
// of 1/64 voxel steps refined by a Lipschitz bound + bisection); the macrocell baseline gives the
// same first hits; the sphere field's hits lie on the sphere within the trilinear error bound.
// Seeded. PENUMBRA_VOLUME_RAYS=N sets the rays per field (default 5000: 20k in all).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "core/volume/macrocell_grid.h"
#include "core/volume/octree_trace.h"
#include "scenegen/volume_fields.h"

namespace penumbra {
namespace {

using volume::DenseGrid;

int raysPerField() {
  const char* env = std::getenv("PENUMBRA_VOLUME_RAYS");
  return env ? std::max(1, std::atoi(env)) : 5000;
}

// ---- The reference: everything below until "checks" is written without core/volume. ----
template <class T>
double refVoxel(const DenseGrid<T>& g, int x, int y, int z) {
  if (x < 0 || y < 0 || z < 0 || x >= g.size.x || y >= g.size.y || z >= g.size.z) return 0.0;
  return double(g.values[(size_t(z) * g.size.y + y) * g.size.x + x]);
}

template <class T>
double refField(const DenseGrid<T>& g, const Vec3& p) {
  const double fx = std::floor(p.x), fy = std::floor(p.y), fz = std::floor(p.z);
  const int x = int(fx), y = int(fy), z = int(fz);
  const double u = p.x - fx, v = p.y - fy, w = p.z - fz;
  auto lerp = [](double a, double b, double s) { return a + (b - a) * s; };
  const double c00 = lerp(refVoxel(g, x, y, z), refVoxel(g, x + 1, y, z), u);
  const double c10 = lerp(refVoxel(g, x, y + 1, z), refVoxel(g, x + 1, y + 1, z), u);
  const double c01 = lerp(refVoxel(g, x, y, z + 1), refVoxel(g, x + 1, y, z + 1), u);
  const double c11 = lerp(refVoxel(g, x, y + 1, z + 1), refVoxel(g, x + 1, y + 1, z + 1), u);
  return lerp(lerp(c00, c10, v), lerp(c01, c11, v), w);
}

struct RefResult {
  double entry = 0.0;       // where the march started (the box entry)
  std::optional<double> t;  // the first hit
};

// A Lipschitz constant of the trilinear field along a unit direction: each gradient
// component interpolates differences along its axis, so |∇f| ≤ √3 · the largest neighbour
// difference (outside = 0 included).
template <class T>
double refLipschitz(const DenseGrid<T>& g) {
  double largest = 0.0;
  for (int z = -1; z < g.size.z; ++z)
    for (int y = -1; y < g.size.y; ++y)
      for (int x = -1; x < g.size.x; ++x) {
        const double v = refVoxel(g, x, y, z);
        largest = std::max({largest, std::abs(refVoxel(g, x + 1, y, z) - v),
                            std::abs(refVoxel(g, x, y + 1, z) - v),
                            std::abs(refVoxel(g, x, y, z + 1) - v)});
      }
  return std::sqrt(3.0) * largest;
}

// First sign change of f − iso (f > iso against f ≤ iso) along origin + t·dir (unit dir)
// inside [0, size − 1]³: march in small steps; a step whose ends agree in sign is split
// while the Lipschitz bound allows a root pair inside it (|g(a)| + |g(b)| ≤ L·(b − a)),
// down to 1e-10; a bracketing step is bisected.
template <class T>
RefResult refFirstHit(const DenseGrid<T>& g, double lipschitz, const Vec3& origin, const Vec3& dir,
                      double iso, double step) {
  double t0 = 0.0, t1 = 1e300;
  for (int a = 0; a < 3; ++a) {
    const double hi = g.size[a] - 1;
    if (dir[a] == 0.0) {
      if (origin[a] < 0.0 || origin[a] > hi) return {};
      continue;
    }
    double ta = (0.0 - origin[a]) / dir[a], tb = (hi - origin[a]) / dir[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta), t1 = std::min(t1, tb);
  }
  if (t0 > t1) return {};
  auto gAt = [&](double t) { return refField(g, origin + dir * t) - iso; };
  // The first bracket [a, b] (sign change) inside [a, b], or none.
  std::function<std::optional<std::pair<double, double>>(double, double, double, double)> bracket =
      [&](double a, double b, double ga, double gb) -> std::optional<std::pair<double, double>> {
    if ((ga > 0.0) != (gb > 0.0)) return std::pair{a, b};
    if (b - a < 1e-10 || std::abs(ga) + std::abs(gb) > lipschitz * (b - a)) return std::nullopt;
    const double m = 0.5 * (a + b), gm = gAt(m);
    if (auto left = bracket(a, m, ga, gm)) return left;
    return bracket(m, b, gm, gb);
  };
  double ta = t0, ga = gAt(ta);
  while (ta < t1) {
    const double tb = std::min(ta + step, t1), gb = gAt(tb);
    if (const auto found = bracket(ta, tb, ga, gb)) {
      double lo = found->first, hi = found->second;
      const bool sLo = gAt(lo) > 0.0;
      for (int i = 0; i < 80; ++i) {
        const double mid = 0.5 * (lo + hi);
        ((gAt(mid) > 0.0) == sLo ? lo : hi) = mid;
      }
      return {t0, 0.5 * (lo + hi)};
    }
    ta = tb, ga = gb;
  }
  return {t0, std::nullopt};
}
// ---- checks ----

struct RayCase {
  Vec3 origin, dir;
};

// Rays from a box 1.5× the volume's towards a random point inside it (many start inside).
std::vector<RayCase> randomRays(glm::ivec3 size, int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<RayCase> rays;
  const Vec3 hi = Vec3(size - 1);
  while (int(rays.size()) < count) {
    const Vec3 from = (Vec3(u(rng), u(rng), u(rng)) * 2.0 - 0.5) * hi;
    const Vec3 to = Vec3(u(rng), u(rng), u(rng)) * hi;
    if (glm::length(to - from) < 1e-3) continue;
    rays.push_back({from, glm::normalize(to - from)});
  }
  return rays;
}

struct Agreement {
  int hits = 0, misses = 0, coarseReference = 0;
};

// Octree against the reference on one field: equal hits to 1e-6 voxel, equal misses. A hit
// the octree finds earlier would count as the reference's miss only if it were a genuine sign
// change of the reference field inside a march step whose ends agree in sign (a root pair
// closer than the reference's 1e-10 floor): none are allowed.
template <class T>
Agreement compareWithReference(const DenseGrid<T>& grid, double iso,
                               const std::vector<RayCase>& rays, const std::string& what) {
  const auto octree = volume::OctreeVolume<T>::build(grid);
  const volume::MacrocellGrid<T> macro(grid, 4);
  Agreement out;
  constexpr double kStep = 1.0 / 64.0;
  const double lipschitz = refLipschitz(grid);
  for (const RayCase& ray : rays) {
    const volume::VolumeRay vray{ray.origin, ray.dir};
    const auto got = volume::traceOctree(octree, vray, iso);
    const auto grid_hit = macro.trace(vray, iso);
    const RefResult ref = refFirstHit(grid, lipschitz, ray.origin, ray.dir, iso, kStep);
    const std::optional<double>& want = ref.t;
    EXPECT_EQ(got.has_value(), grid_hit.has_value()) << what << " macrocell";
    if (got && grid_hit) {
      EXPECT_NEAR(got->t, grid_hit->t, 1e-9) << what << " macrocell";
    }
    if (got && (!want || got->t < *want - 1e-6)) {
      // Independent confirmation: a sign change of the reference field at got->t …
      auto f = [&](double t) { return refField(grid, ray.origin + ray.dir * t) - iso; };
      EXPECT_NE(f(got->t - 1e-7) > 0.0, f(got->t + 1e-7) > 0.0)
          << what << " octree hit is not a root at t=" << got->t;
      // … inside a march step whose ends agree in sign (the march could not see it).
      const double a = ref.entry + std::floor((got->t - ref.entry) / kStep) * kStep;
      EXPECT_EQ(f(a) > 0.0, f(a + kStep) > 0.0) << what << " the march should have seen it";
      ADD_FAILURE() << what << " octree hit at t=" << got->t << " before the reference's";
      ++out.coarseReference;
      continue;
    }
    EXPECT_EQ(got.has_value(), want.has_value())
        << what << " ray from " << ray.origin.x << "," << ray.origin.y << "," << ray.origin.z;
    if (got.has_value() != want.has_value()) continue;
    if (!got) {
      ++out.misses;
      continue;
    }
    ++out.hits;
    EXPECT_NEAR(got->t, *want, 1e-6) << what;
    // The normal is the trilinear gradient: away from cell faces, against central differences.
    const Vec3 p = ray.origin + ray.dir * got->t;
    const Vec3 frac = p - glm::floor(p);
    if (glm::all(glm::greaterThan(frac, Vec3(0.01))) && glm::all(glm::lessThan(frac, Vec3(0.99)))) {
      Vec3 g;
      for (int a = 0; a < 3; ++a) {
        Vec3 e(0.0);
        e[a] = 1e-5;
        g[a] = (refField(grid, p + e) - refField(grid, p - e)) / 2e-5;
      }
      if (glm::length(g) > 1e-3 * (octree.rootMax() - octree.rootMin())) {
        EXPECT_GT(glm::dot(got->normal, glm::normalize(g)), 0.9999) << what;
      }
    }
  }
  return out;
}

template <class T>
void expectAgreement(const DenseGrid<T>& grid, double iso, uint64_t seed, const std::string& what) {
  const int count = raysPerField();
  const Agreement a = compareWithReference(grid, iso, randomRays(grid.size, count, seed), what);
  std::printf("%s: %d rays, %d hits, %d misses, %d finer than the reference's march\n",
              what.c_str(), count, a.hits, a.misses, a.coarseReference);
  EXPECT_GT(a.hits, count / 10) << what;
}

TEST(VolumeTrace, OctreeHitsMatchIndependentMarch) {
  // Non-integer isovalues: the 8- and 16-bit data never sit exactly on them.
  expectAgreement(quantise8(makeVolumeField({VolumeField::MarschnerLobb, {41, 41, 41}, 1})), 127.37,
                  21, "marschner-lobb-8");
  expectAgreement(quantise16(makeVolumeField({VolumeField::Smoke, {33, 40, 29}, 2})), 9000.5, 22,
                  "smoke-16");
  expectAgreement(quantise8(makeVolumeField({VolumeField::MixingLayer, {37, 37, 37}, 3})), 100.25,
                  23, "mixing-8");
  expectAgreement(makeVolumeField({VolumeField::Sphere, {32, 31, 33}, 4}), 0.5123, 24,
                  "sphere-float");
}

// Rays along cell faces and edges and through cell corners: ties in the octant order, spans of
// zero length, a ray lying in the face two cells share.
std::vector<RayCase> latticeRays(glm::ivec3 size, int count, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::vector<RayCase> rays;
  const Vec3 dirs[] = {{1, 0, 0},  {0, -1, 0}, {0, 0, 1},  {1, 1, 0},
                       {0, -1, 1}, {1, 1, 1},  {-1, 1, -1}};
  while (int(rays.size()) < count) {
    const Vec3 dir = glm::normalize(dirs[rng() % std::size(dirs)]);
    Vec3 at;  // a lattice point (or half-way between) inside, then stepped back outside
    for (int a = 0; a < 3; ++a) at[a] = double(rng() % (2 * (size[a] - 1) + 1)) * 0.5;
    const double back = rng() % 3 == 0 ? 0.0 : double(size.x + size.y + size.z);
    rays.push_back({at - dir * back, dir});
  }
  return rays;
}

TEST(VolumeTrace, RaysAlongCellFacesEdgesAndCorners) {
  const auto ml = quantise8(makeVolumeField({VolumeField::MarschnerLobb, {33, 30, 35}, 1}));
  const auto mixing = quantise8(makeVolumeField({VolumeField::MixingLayer, {40, 33, 37}, 2}));
  const auto smoke = quantise16(makeVolumeField({VolumeField::Smoke, {35, 35, 35}, 3}));
  const Agreement a = compareWithReference(ml, 127.37, latticeRays(ml.size, 1500, 41), "ml");
  const Agreement b =
      compareWithReference(mixing, 100.25, latticeRays(mixing.size, 1500, 42), "mix");
  const Agreement c =
      compareWithReference(smoke, 9000.5, latticeRays(smoke.size, 1500, 43), "smoke");
  std::printf("lattice rays: %d, %d, %d hits\n", a.hits, b.hits, c.hits);
  EXPECT_GT(a.hits, 100);
  EXPECT_GT(b.hits, 100);
  EXPECT_GT(c.hits, 100);
}

TEST(VolumeTrace, SphereHitsLieOnTheSphereWithinTheTrilinearBound) {
  const glm::ivec3 size(48, 47, 49);
  const DenseGrid<float> grid = makeVolumeField({VolumeField::Sphere, size, 1});
  const SphereGeometry sphere = sphereGeometry(size);
  const auto octree = volume::OctreeVolume<float>::build(grid);
  int hits = 0;
  double worst = 0.0;
  for (const RayCase& ray : randomRays(size, raysPerField(), 31)) {
    const auto hit = volume::traceOctree(octree, {ray.origin, ray.dir}, 0.5);
    if (!hit) continue;
    ++hits;
    const Vec3 p = ray.origin + ray.dir * hit->t;
    const double r = glm::length(p - sphere.centre);
    // f = 0.5 + k(R − r): |∂²f/∂x_a²| ≤ k/r_min on a cell, so trilinear interpolation errs by
    // at most 3k/(8 r_min) in value, 3/(8 r_min) in distance (r_min = r − √3, the cell's
    // nearest point to the centre); plus float storage: 2^−24 in value, /k in distance.
    const double bound =
        3.0 / (8.0 * (r - std::sqrt(3.0))) + std::ldexp(1.0, -24) / sphere.valuePerVoxel;
    EXPECT_LE(std::abs(r - sphere.radius), bound) << "r=" << r;
    worst = std::max(worst, std::abs(r - sphere.radius) / bound);
    // The normal points inwards (the field grows towards the centre).
    EXPECT_GT(glm::dot(hit->normal, glm::normalize(sphere.centre - p)), 0.99);
  }
  std::printf("sphere: %d hits, worst |r − R| / bound = %.3f\n", hits, worst);
  EXPECT_GT(hits, raysPerField() / 4);
}

}  // namespace
}  // namespace penumbra
