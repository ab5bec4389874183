// DmTree::insert beats while one large shadow goes in (a model's shadow on the floor: ten thousand
// segments, seconds in one insert), so a build's progress sees the work go on and a cancel thrown
// from the beat lands within it, not after it; the tree thrown out of is destroyed cleanly (the
// sanitizer build checks). Seeded shadows of many internal chords, as a silhouette's lines cross.
#include <gtest/gtest.h>

#include <functional>
#include <stdexcept>

#include "tests/core/dmtree/shadow_fixtures.h"

namespace penumbra::dmtree_test {
namespace {

// A penumbra over most of the receiver [-1, 1]², no umbra, and `chords` internal segments across it.
SingleShadow manyChords(Rng& rng, size_t chords) {
  SingleShadow s;
  s.light = 0;
  s.occluder = FaceId{7, 0};
  s.penumbra = rect(-0.9, -0.9, 0.9, 0.9);
  addRegionSegments(s, s.penumbra, SegmentKind::Penumbra);
  for (size_t k = 0; k < chords; ++k) {
    const Vec2 p{uniform(rng, -0.8, 0.8), uniform(rng, -0.8, 0.8)};
    const double angle = uniform(rng, 0, 2 * M_PI);
    CriticalSegment seg;
    seg.kind = SegmentKind::Internal;
    seg.lightElement = {ElementRef::Kind::Edge, uint32_t(k % 4)};
    seg.occluderElement = {ElementRef::Kind::Vertex, uint32_t(k)};
    seg.a = p;
    seg.b = p + 0.15 * Vec2{std::cos(angle), std::sin(angle)};
    s.segments.push_back(seg);
  }
  return s;
}

struct Stop : std::runtime_error {
  Stop() : std::runtime_error("stop") {}
};

TEST(InsertBeat, ALargeShadowBeatsAsItGoesInAndAThrowFromTheBeatEndsTheInsert) {
  const Polygon2 receiver = rect(-1, -1, 1, 1);
  for (uint64_t seed = 1; seed <= 3; ++seed) {
    SCOPED_TRACE("seed " + std::to_string(seed));
    Rng rng(seed);
    const size_t chords = 2000;
    const SingleShadow shadow = manyChords(rng, chords);

    size_t beats = 0;
    const std::function<void()> count = [&] { ++beats; };
    DmTree counted(receiver, kTol);
    const InsertResult result = counted.insert(shadow, count);
    // buildSingleTree's beats alone are one per kSegmentsPerBeat segments; the merge adds one per
    // kCellsPerBeat splits.
    EXPECT_GE(beats, shadow.segments.size() / kSegmentsPerBeat + result.nodesAdded / DmTree::kCellsPerBeat - 1);
    EXPECT_GT(result.nodesAdded, 2 * DmTree::kCellsPerBeat) << "the shadow splits the receiver little";

    // Without a beat, the same tree (the beat changes nothing).
    DmTree plain(receiver, kTol);
    plain.insert(shadow);
    EXPECT_EQ(plain.cellCount(), counted.cellCount());
    EXPECT_EQ(plain.vertexCount(), counted.vertexCount());

    // A throw from the k-th beat ends the insert there: it propagates, and the tree is dropped.
    for (size_t stopAt : {size_t(1), beats / 2, beats}) {
      size_t seen = 0;
      const std::function<void()> stop = [&] {
        if (++seen == stopAt) throw Stop();
      };
      auto tree = std::make_unique<DmTree>(receiver, kTol);
      EXPECT_THROW(tree->insert(shadow, stop), Stop) << "beat " << stopAt;
      EXPECT_EQ(seen, stopAt);
      tree.reset();
    }
  }
}

}  // namespace
}  // namespace penumbra::dmtree_test
