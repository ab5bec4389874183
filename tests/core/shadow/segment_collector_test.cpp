// SegmentCollector (core/shadow/critical_wedge.h) drops a segment equal within eps to an
// earlier one of the same kind. Past its first segments it finds them through a grid of their
// ends; seeded random sets full of near copies (ends moved by up to 1.5·eps, reversed, on and
// off the grid's cell lines, far from the origin) keep exactly what a scan over every kept
// segment keeps, in the same order.
#include "core/shadow/critical_wedge.h"

#include <gtest/gtest.h>

#include <random>
#include <vector>

namespace penumbra {
namespace {

// The rule written out: a segment is kept unless an earlier kept one of its kind has the same
// ends within eps, either way round.
std::vector<CriticalSegment> keptByScan(const std::vector<CriticalSegment>& added, double eps) {
  auto near = [&](const Vec2& p, const Vec2& q) { return glm::length(p - q) <= eps; };
  std::vector<CriticalSegment> kept;
  for (const CriticalSegment& s : added) {
    bool duplicate = false;
    for (const CriticalSegment& k : kept)
      duplicate = duplicate || (k.kind == s.kind && ((near(k.a, s.a) && near(k.b, s.b)) ||
                                                     (near(k.a, s.b) && near(k.b, s.a))));
    if (!duplicate) kept.push_back(s);
  }
  return kept;
}

TEST(SegmentCollector, KeepsWhatAScanOverEveryKeptSegmentKeeps) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t dropped = 0, keptPastIndex = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const double eps = trial % 2 ? 1e-9 : 1e-6;
    // Coordinates near the origin, or far off it (2·eps cells numbered past 2^31).
    const Vec2 origin = trial % 4 < 2 ? Vec2(0.0) : Vec2(3e3, -7e3);
    const double size = 1e3 * eps * (1 + trial % 3);  // a few thousand cells across
    const Polygon2 receiver = {origin + Vec2(-1e6, -1e6), origin + Vec2(1e6, -1e6), origin + Vec2(1e6, 1e6),
                               origin + Vec2(-1e6, 1e6)};
    SegmentCollector collector(receiver, receiver, {}, eps);
    std::vector<CriticalSegment> added;
    const int count = 30 + int(rng() % 600);
    for (int i = 0; i < count; ++i) {
      CriticalSegment s;
      s.kind = SegmentKind(rng() % 3);
      if (!added.empty() && rng() % 2) {  // a near copy of an earlier one
        const CriticalSegment& earlier = added[rng() % added.size()];
        auto moved = [&](const Vec2& p) {
          const double angle = 6.283185307179586 * unit(rng), r = 1.5 * eps * unit(rng);
          return p + r * Vec2(std::cos(angle), std::sin(angle));
        };
        s.a = moved(earlier.a), s.b = moved(earlier.b);
        if (rng() % 2) std::swap(s.a, s.b);
        if (rng() % 4 == 0) s.kind = earlier.kind;
        else if (rng() % 3 == 0) s.kind = SegmentKind((int(earlier.kind) + 1) % 3);
        else s.kind = earlier.kind;
      } else {
        // Ends on the grid's cell lines (multiples of 2·eps) or anywhere.
        auto point = [&] {
          Vec2 p(size * unit(rng), size * unit(rng));
          if (rng() % 3 == 0) p = 2 * eps * glm::floor(p / (2 * eps));
          return origin + p;
        };
        s.a = point(), s.b = point();
      }
      if (glm::length(s.a - s.b) <= 4 * eps) continue;
      added.push_back(s);
      collector.addWhole(s.a, s.b, s.kind, {}, {});
    }
    const std::vector<CriticalSegment> expected = keptByScan(added, eps);
    const std::vector<CriticalSegment> kept = collector.take();
    ASSERT_EQ(kept.size(), expected.size()) << "trial " << trial;
    for (size_t i = 0; i < kept.size(); ++i) {
      EXPECT_EQ(kept[i].a, expected[i].a) << "trial " << trial << " segment " << i;
      EXPECT_EQ(kept[i].b, expected[i].b) << "trial " << trial << " segment " << i;
      EXPECT_EQ(kept[i].kind, expected[i].kind) << "trial " << trial << " segment " << i;
    }
    dropped += added.size() - kept.size();
    keptPastIndex += kept.size() > 32 ? kept.size() - 32 : 0;
  }
  EXPECT_GT(dropped, 1000u);
  EXPECT_GT(keptPastIndex, 1000u);
}

}  // namespace
}  // namespace penumbra
