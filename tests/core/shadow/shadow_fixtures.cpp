#include "tests/core/shadow/shadow_fixtures.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/reference/exact_irradiance.h"
#include "core/shadow/cast_shadow.h"

namespace penumbra::testing {

namespace {

Object singleFace(const std::string& id, const Polygon3& polygon) {
  Object object;
  object.id = id;
  object.vertices = polygon;
  std::vector<int> face;
  for (int i = 0; i < int(polygon.size()); ++i) face.push_back(i);
  object.faces.push_back(face);
  return object;
}

std::string str(const Vec3& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x << ", " << p.y << ", " << p.z << ")";
  return s.str();
}

// Uniform point in a convex polygon (fan triangles weighted by area).
Vec2 uniformIn(const Polygon2& polygon, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<double> cumulative;
  double total = 0;
  for (size_t i = 1; i + 1 < polygon.size(); ++i) {
    total += std::abs(cross2(polygon[i] - polygon[0], polygon[i + 1] - polygon[0])) / 2;
    cumulative.push_back(total);
  }
  const double pick = unit(rng) * total;
  size_t t = std::lower_bound(cumulative.begin(), cumulative.end(), pick) - cumulative.begin();
  t = std::min(t, cumulative.size() - 1);
  double r1 = unit(rng), r2 = unit(rng);
  if (r1 + r2 > 1) r1 = 1 - r1, r2 = 1 - r2;
  return polygon[0] + r1 * (polygon[t + 1] - polygon[0]) + r2 * (polygon[t + 2] - polygon[0]);
}

double segmentDistance(const Vec2& a, const Vec2& b, const Vec2& p) {
  const Vec2 d = b - a;
  const double t = std::clamp(glm::dot(p - a, d) / glm::dot(d, d), 0.0, 1.0);
  return glm::length(p - (a + t * d));
}

// Closest-approach parameters of lines p + t·d and q + u·e.
void closest(const Vec3& p, const Vec3& d, const Vec3& q, const Vec3& e, double* t, double* u) {
  const Vec3 w = p - q;
  const double a = glm::dot(d, d), b = glm::dot(d, e), c = glm::dot(e, e);
  const double dd = glm::dot(d, w), ee = glm::dot(e, w);
  const double den = a * c - b * b;
  *t = (b * ee - c * dd) / den;
  *u = (a * ee - b * dd) / den;
}

}  // namespace

Tiny makeTiny(const Light& light, const Polygon3& occluder, const Polygon3& receiver) {
  return Tiny{Scene({light}, {}, {singleFace("occluder", occluder), singleFace("receiver", receiver)})};
}

Polygon3 facing(Polygon3 polygon, const Vec3& front) {
  if (glm::dot(newellVector(polygon), front) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

Light squareLight(const Vec3& centre, double half, const Vec3& front) {
  const Vec3 n = glm::normalize(front);
  const Vec3 a = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 u = glm::normalize(glm::cross(a, n)), v = glm::cross(n, u);
  Light light;
  light.id = "light";
  light.polygon = facing({centre - half * u - half * v, centre + half * u - half * v,
                          centre + half * u + half * v, centre - half * u + half * v},
                         n);
  light.radiance = Vec3(1.0);
  return light;
}

double signedDistance(const Polygon2& polygon, const Vec2& p) {
  if (polygon.size() < 3) return -std::numeric_limits<double>::infinity();
  double inside = std::numeric_limits<double>::infinity();
  double outside = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    if (a == b) continue;
    inside = std::min(inside, lineDistance(a, b, p));
    outside = std::min(outside, segmentDistance(a, b, p));
  }
  return inside >= 0 ? inside : -outside;
}

RegionCounts checkRegions(const Tiny& tiny, const std::optional<SingleShadow>& shadow,
                          std::mt19937_64& rng, int samples, double margin,
                          const std::string& label) {
  RegionCounts counts;
  const ExactReference reference(tiny.scene);
  const PlaneFrame frame = tiny.frame();
  Polygon2 receiver2;
  for (const Vec3& p : tiny.receiver().polygon) receiver2.push_back(frame.to2D(p));
  receiver2 = counterClockwise(receiver2);
  const Polygon2 empty;
  const Polygon2& penumbra = shadow ? shadow->penumbra : empty;
  const Polygon2& umbra = shadow ? shadow->umbra : empty;

  // Near the penumbra: its bounding box grown by a quarter, points kept if on R.
  Vec2 lo{0.0}, hi{0.0};
  if (!penumbra.empty()) {
    lo = hi = penumbra[0];
    for (const Vec2& p : penumbra) lo = glm::min(lo, p), hi = glm::max(hi, p);
    const Vec2 grow = 0.25 * (hi - lo);
    lo -= grow;
    hi += grow;
  }
  std::uniform_real_distribution<double> unit(0, 1);
  int reported = 0;
  for (int i = 0; i < samples; ++i) {
    Vec2 u = uniformIn(receiver2, rng);
    if (!penumbra.empty() && i % 2 == 1) {
      const Vec2 near{lo.x + unit(rng) * (hi.x - lo.x), lo.y + unit(rng) * (hi.y - lo.y)};
      if (contains(receiver2, near, 0)) u = near;
    }
    ++counts.samples;
    const double dp = signedDistance(penumbra, u), du = signedDistance(umbra, u);
    const bool judgePenumbra = std::abs(dp) > margin, judgeUmbra = std::abs(du) > margin;
    if (!judgePenumbra || (dp > 0 && !judgeUmbra)) continue;
    const Vec3 p = frame.to3D(u);
    const LightVisibility v = reference.visibility(p, tiny.receiver().plane.normal, 0);
    const bool hidden = v.lightClass != LightClass::Lit;
    const bool allHidden = v.lightClass == LightClass::Umbra;
    // Classes must agree with the factors (a check of the reference we lean on).
    const bool factorsAgree = !hidden || v.visibleFactor < v.unoccludedFactor;
    bool ok = factorsAgree;
    if (dp < 0) {
      ok = ok && !hidden;
      ++counts.outside;
    } else if (du > 0) {
      ok = ok && allHidden;
      ++counts.umbra;
    } else {
      ok = ok && hidden && !allHidden;
      ++counts.penumbra;
    }
    if (!ok) {
      ++counts.mismatches;
      if (reported++ < 3)
        ADD_FAILURE() << label << ": point " << str(p) << " penumbra distance " << dp
                      << " umbra distance " << du << " reference class "
                      << toString(v.lightClass) << " visible " << v.visibleFactor << " of "
                      << v.unoccludedFactor;
    }
  }
  return counts;
}

int checkSegments(const Tiny& tiny, const SingleShadow& shadow, std::mt19937_64& rng,
                  const std::string& label) {
  const Tolerance tol = tiny.scene.tolerance();
  const double eps = tol.length(), near = tol.onPlane();
  const auto pair = castingPair(tiny.scene, 0, tiny.occluder(), tiny.receiver());
  if (!pair) {
    ADD_FAILURE() << label << ": a shadow without a casting pair";
    return 1;
  }
  const PlaneFrame frame = tiny.frame();
  Polygon2 receiver2;
  for (const Vec3& p : tiny.receiver().polygon) receiver2.push_back(frame.to2D(p));
  receiver2 = counterClockwise(receiver2);
  const Polygon3& light = pair->light;
  const Polygon3& occ = pair->occluder;
  std::uniform_real_distribution<double> unit(0, 1);
  int failures = 0;
  auto fail = [&](const CriticalSegment& s, const std::string& what, const Vec3& x) {
    if (failures++ < 5)
      ADD_FAILURE() << label << ": segment kind " << int(s.kind) << " light element "
                    << int(s.lightElement.kind) << ":" << s.lightElement.index << " occluder element "
                    << int(s.occluderElement.kind) << ":" << s.occluderElement.index << " at "
                    << str(x) << ": " << what;
  };
  for (const CriticalSegment& s : shadow.segments) {
    if (!(glm::length(s.b - s.a) > eps)) fail(s, "degenerate", frame.to3D(s.a));
    for (double t : {0.0, 0.5, 1.0, unit(rng)}) {
      const Vec2 u = s.a + t * (s.b - s.a);
      const Vec3 x = frame.to3D(u);
      if (!contains(receiver2, u, eps)) fail(s, "outside the receiver", x);
      if (!contains(shadow.penumbra, u, eps)) fail(s, "outside the closed penumbra", x);
      if (signedDistance(shadow.umbra, u) > eps) fail(s, "inside the open umbra", x);
      const bool ve = s.lightElement.kind == ElementRef::Kind::Vertex;
      if (ve != (s.occluderElement.kind == ElementRef::Kind::Edge)) {
        fail(s, "neither VE nor EV", x);
        continue;
      }
      if (ve) {
        const Vec3 sv = light.at(s.lightElement.index);
        const Vec3 a = occ.at(s.occluderElement.index), b = occ[(s.occluderElement.index + 1) % occ.size()];
        if (s.kind == SegmentKind::Contact) {
          // The contact edge itself: on the occluder edge, in R's plane.
          double along = glm::dot(x - a, b - a) / glm::dot(b - a, b - a);
          along = std::clamp(along, 0.0, 1.0);
          if (glm::length(x - (a + along * (b - a))) > near) fail(s, "contact off its occluder edge", x);
          continue;
        }
        const Vec3 n = glm::normalize(glm::cross(a - sv, b - sv));
        if (std::abs(glm::dot(n, x - sv)) > near) fail(s, "not in the VE plane", x);
        // Ray s→x meets the edge between its end points, between s and x.
        double tr = 0, ue = 0;
        closest(sv, x - sv, a, b - a, &tr, &ue);
        const double slack = near / glm::length(b - a);
        if (!(ue >= -slack && ue <= 1 + slack)) fail(s, "ray misses the occluder edge", x);
        if (!(tr > 0 && tr <= 1 + near / glm::length(x - sv))) fail(s, "edge not between light and point", x);
      } else {
        const Vec3 v = occ.at(s.occluderElement.index);
        const Vec3 p = light.at(s.lightElement.index), q = light[(s.lightElement.index + 1) % light.size()];
        const Vec3 n = glm::normalize(glm::cross(v - p, v - q));
        if (std::abs(glm::dot(n, x - v)) > near) fail(s, "not in the EV plane", x);
        // Ray x→v meets the light edge, beyond v.
        double tr = 0, ue = 0;
        closest(x, v - x, p, q - p, &tr, &ue);
        const double slack = near / glm::length(q - p);
        if (!(ue >= -slack && ue <= 1 + slack)) fail(s, "ray misses the light edge", x);
        if (!(tr >= 1 - near / glm::length(v - x))) fail(s, "occluder vertex not between point and light", x);
      }
    }
    // Kind against the regions, at the midpoint.
    const Vec2 mid = 0.5 * (s.a + s.b);
    const double dp = signedDistance(shadow.penumbra, mid), du = signedDistance(shadow.umbra, mid);
    switch (s.kind) {
      case SegmentKind::Penumbra:
        if (std::abs(dp) > eps) fail(s, "penumbra segment off the penumbra boundary", frame.to3D(mid));
        break;
      case SegmentKind::Umbra:
        if (std::abs(du) > eps) fail(s, "umbra segment off the umbra boundary", frame.to3D(mid));
        break;
      case SegmentKind::Internal:
        if (!(dp > eps)) fail(s, "internal segment on the penumbra boundary", frame.to3D(mid));
        break;
      case SegmentKind::Contact:
        if (std::abs(tiny.occluder().plane.signedDistance(frame.to3D(mid))) > near)
          fail(s, "contact segment off the occluder's plane", frame.to3D(mid));
        break;
    }
  }
  return failures;
}

}  // namespace penumbra::testing
