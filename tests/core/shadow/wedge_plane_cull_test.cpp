// wedgePlaneMisses (core/shadow/critical_wedge.h) culls a silhouette wedge before wedgeChord
// only where wedgeChord would give nothing. Seeded random receivers (triangles and quads, 1e-3
// to 10 across, scene sizes 1 and 1e3) and VE/EV wedges whose plane runs along a receiver edge
// at 0 to 3·eps off it, or crosses the receiver, or passes far from it: whenever the cull says
// the plane misses, wedgeChord gives no chord. Planes within eps of an edge make chords that a
// tighter cull (a margin under eps) would drop, so the test fails for such a cull.
#include "core/shadow/critical_wedge.h"

#include <gtest/gtest.h>

#include <random>

#include "core/geom/convex2d.h"
#include "core/geom/plane_frame.h"

namespace penumbra {
namespace {

TEST(WedgePlaneCull, DropsOnlyWedgesWhoseChordIsEmpty) {
  std::mt19937_64 rng(43);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  size_t culled = 0, chords = 0, nearChords = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    const Tolerance tol = Tolerance::forSize(trial % 2 ? 1.0 : 1e3);
    const double eps = tol.length();
    const double size = std::pow(10.0, -3 + 4 * unit(rng));
    // The receiver: a triangle or quad in a tilted plane through a random point.
    const Vec3 normal = glm::normalize(Vec3(unit(rng) - 0.5, 1.0, unit(rng) - 0.5));
    const Vec3 centre(unit(rng) * 5, unit(rng) * 2, unit(rng) * 5);
    const PlaneFrame frame = PlaneFrame::onPlane(Plane::throughPoint(normal, centre), centre);
    Polygon2 outline;
    const int corners = 3 + trial % 2;
    for (int k = 0; k < corners; ++k) {
      const double angle = (k + 0.4 * unit(rng)) * 2 * M_PI / corners;
      outline.push_back(size * Vec2(std::cos(angle), std::sin(angle)));
    }
    outline = counterClockwise(outline);
    Polygon3 receiver;
    for (const Vec2& p : outline) receiver.push_back(frame.to3D(p));

    // A line in the receiver's plane: along edge 0 shifted 0–3·eps outwards or inwards, across
    // the receiver, or far off it; the wedge's plane holds it and a light point above.
    const Vec2 a = outline[0], b = outline[1];
    const Vec2 outward = glm::normalize(Vec2(b.y - a.y, a.x - b.x));
    Vec2 from, to;
    const int kind = trial % 3;
    if (kind == 0) {
      const Vec2 shift = (unit(rng) < 0.5 ? 1.0 : -1.0) * 3 * eps * unit(rng) * outward;
      from = a + shift - (b - a), to = b + shift + (b - a);
    } else if (kind == 1) {
      from = outline[0] - (outline[2] - outline[0]), to = outline[2] + (outline[2] - outline[0]);
    } else {
      const Vec2 offset = (2 + unit(rng)) * size * outward;
      from = a + offset - (b - a), to = b + offset + (b - a);
    }
    const Vec3 light = frame.to3D(0.5 * (from + to)) + (1 + 2 * unit(rng)) * normal +
                       Vec3(unit(rng) - 0.5, 0.0, unit(rng) - 0.5);
    const Vec3 p = frame.to3D(from), q = frame.to3D(to);
    const double t = 0.2 + 0.6 * unit(rng);
    const ElementRef vertex{ElementRef::Kind::Vertex, 0}, edge{ElementRef::Kind::Edge, 0};
    // VE: light vertex `light`, occluder edge on the segments light→p and light→q; EV: a
    // light edge through `light` along pq, the occluder vertex between it and the line.
    const std::optional<Wedge> wedge =
        trial % 2 ? vertexEdgeWedge(vertex, edge, light, light + t * (p - light), light + t * (q - light), eps)
                  : edgeVertexWedge(edge, vertex, light - 0.5 * (q - p), light + 0.5 * (q - p),
                                    light + t * (0.5 * (p + q) - light), eps);
    ASSERT_TRUE(wedge);
    const auto chord = wedgeChord(*wedge, outline, frame, tol);
    if (wedgePlaneMisses(*wedge, receiver, eps)) {
      ++culled;
      EXPECT_FALSE(chord) << "trial " << trial << ": a culled wedge has a chord";
    }
    if (chord) ++chords;
    if (chord && kind == 0) ++nearChords;
  }
  // Each way is exercised: culled wedges, chords, and chords of planes within 3·eps of an edge.
  EXPECT_GT(culled, 1000u);
  EXPECT_GT(chords, 1000u);
  EXPECT_GT(nearChords, 100u);
}

}  // namespace
}  // namespace penumbra
