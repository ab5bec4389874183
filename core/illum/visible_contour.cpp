#include "core/illum/visible_contour.h"

#include <algorithm>
#include <bit>
#include <cmath>

#include "core/geom/fingerprint.h"

namespace penumbra {

namespace {

// Every point of `inner` inside the convex polygon with edge lines `lines`, or
// within eps of it.
template <class Line>
bool holdsAll(std::span<const Line> lines, std::span<const Vec2> inner, double eps) {
  for (const Line& line : lines)
    for (const Vec2& q : inner)
      if (glm::dot(line.normal, q) - line.offset < -eps) return false;
  return true;
}

}  // namespace

void VisibleContour::addLines(std::span<const Vec2> polygon) {
  for (size_t k = 0; k < polygon.size(); ++k) {
    Line line;  // a zero edge keeps a zero normal: every point "on" it, never deciding
    line.from = polygon[k];
    line.to = polygon[(k + 1) % polygon.size()];
    const Vec2 e = line.to - line.from;
    if (const double length = glm::length(e); length > 0) {
      line.normal = Vec2(-e.y, e.x) / length;
      line.offset = glm::dot(line.normal, line.from);
    }
    lines_.push_back(line);
  }
}

Vec2 VisibleContour::crossing(size_t e, size_t f) const {
  const Line& on = lines_[std::min(e, f)];
  const Line& by = lines_[std::max(e, f)];
  const double dA = glm::dot(by.normal, on.from) - by.offset;
  const double dB = glm::dot(by.normal, on.to) - by.offset;
  const double t = dA != dB ? std::clamp(dA / (dA - dB), 0.0, 1.0) : 0.0;
  return on.from + t * (on.to - on.from);
}

bool VisibleContour::clipToPolygon(size_t edge, size_t first, size_t count, bool alongInside,
                                   bool againstInside, Interval& out) const {
  const Vec2 a = lines_[edge].from, b = lines_[edge].to, d = b - a;
  double t0 = 0, t1 = 1;
  size_t by0 = edge, by1 = edge;  // the lines that set t0, t1 (edge itself: its own ends)
  for (size_t k = first; k < first + count; ++k) {
    const Line& line = lines_[k];
    const double dA = glm::dot(line.normal, a) - line.offset;
    const double dB = glm::dot(line.normal, b) - line.offset;
    if (std::abs(dA) <= eps_ && std::abs(dB) <= eps_) {  // along this edge's line
      if (line.normal == Vec2(0.0)) continue;
      if (glm::dot(line.to - line.from, d) > 0 ? alongInside : againstInside) continue;
      return false;
    }
    if (dA < 0 && dB < 0) return false;
    const double t = dA / (dA - dB);
    if (dA < 0 && t > t0) t0 = t, by0 = k;
    if (dB < 0 && !(dA < 0) && t < t1) t1 = t, by1 = k;
    if (!(t0 < t1)) return false;
  }
  out.from = t0;
  out.to = t1;
  out.fromPoint = by0 == edge ? a : crossing(edge, by0);
  out.toPoint = by1 == edge ? b : crossing(edge, by1);
  return true;
}

void VisibleContour::emitUncovered(Interval within, bool reversed) {
  std::sort(covered_.begin(), covered_.end(),
            [](const Interval& x, const Interval& y) { return x.from < y.from; });
  auto emit = [&](const Vec2& from, const Vec2& to) {
    if (from == to) return;
    boundary_.push_back(reversed ? Segment2{to, from} : Segment2{from, to});
  };
  double t = within.from;
  Vec2 at = within.fromPoint;
  for (const Interval& c : covered_) {
    if (c.to <= t) continue;
    if (c.from >= within.to) break;
    if (c.from > t) emit(at, c.fromPoint);
    if (c.to >= within.to) return;
    t = c.to;
    at = c.toPoint;
  }
  emit(at, within.toPoint);
}

void VisibleContour::clipEdgeOfShadow(uint32_t i, size_t edge) {
  Interval inside;
  if (!clipToPolygon(edge, 0, lightLines_, false, false, inside)) return;
  // Even a stretch shorter than eps is kept: it closes the boundary where a
  // shadow's corner sits at the light's (an open boundary is a wrong integral).
  const Line& line = lines_[edge];
  occluded_ |= (inside.to - inside.from) * glm::length(line.to - line.from) > eps_;
  // Only the stretch inside the light is emitted, so shadows are culled by that stretch's box
  // (the same eps box test as before, on less: a shadow edge crossing the light often runs far
  // beyond it).
  const Vec2 sLow = glm::min(inside.fromPoint, inside.toPoint), sHigh = glm::max(inside.fromPoint, inside.toPoint);
  // Shadow j's part of the edge, if any; a stretch one shadow holds whole leaves nothing
  // (emitUncovered would emit no gap), so the search stops there. The shadow that held the
  // last edge whole is asked first: in clutter a shadow's edges often lie in one other.
  const auto clipBy = [&](uint32_t j, Interval& c) {
    return j != i && !boxesApart(sLow, sHigh, low_[j], high_[j], eps_) &&
           clipToPolygon(edge, firstLine_[j], firstLine_[j + 1] - firstLine_[j], j < i, true, c);
  };
  const auto holdsWhole = [&](const Interval& c) { return c.from <= inside.from && c.to >= inside.to; };
  Interval c;
  if (lastHolder_ < low_.size() && clipBy(lastHolder_, c) && holdsWhole(c)) return;
  if (const uint32_t twin = twinShadow(edge); twin != kNoShadow && clipBy(twin, c) && holdsWhole(c)) return;
  covered_.clear();
  for (uint32_t j : active_) {
    if (!clipBy(j, c)) continue;
    if (holdsWhole(c)) {
      lastHolder_ = j;
      return;
    }
    covered_.push_back(c);
  }
  // The shadow is on the edge's left, the visible part on its right: reversed.
  emitUncovered(inside, true);
}

void VisibleContour::compute(std::span<const Vec2> light, std::span<const Vec2> points,
                             std::span<const uint32_t> starts, double eps, bool sharedEdges) {
  boundary_.clear();
  occluded_ = allCovered_ = false;
  eps_ = eps;
  const size_t count = starts.size() < 2 ? 0 : starts.size() - 1;

  lines_.clear();
  addLines(light);
  lightLines_ = light.size();
  firstLine_.assign(1, uint32_t(lightLines_));
  for (size_t i = 0; i < count; ++i) {
    addLines(points.subspan(starts[i], starts[i + 1] - starts[i]));
    firstLine_.push_back(uint32_t(lines_.size()));
  }
  Vec2 lightLow = light[0], lightHigh = light[0];
  for (const Vec2& v : light) {
    lightLow = glm::min(lightLow, v);
    lightHigh = glm::max(lightHigh, v);
  }
  // Only shadows whose box meets the light's take part; one holding the whole
  // light leaves nothing (the umbra of a single face, the common case in clutter).
  active_.clear();
  low_.assign(count, Vec2(0.0));
  high_.assign(count, Vec2(0.0));
  for (size_t i = 0; i < count; ++i) {
    const auto s = points.subspan(starts[i], starts[i + 1] - starts[i]);
    low_[i] = high_[i] = s[0];
    for (const Vec2& v : s) {
      low_[i] = glm::min(low_[i], v);
      high_[i] = glm::max(high_[i], v);
    }
    if (boxesApart(low_[i], high_[i], lightLow, lightHigh, eps)) continue;
    if (holdsAll(std::span<const Line>(lines_).subspan(firstLine_[i], s.size()), light, eps)) {
      occluded_ = allCovered_ = true;
      return;
    }
    active_.push_back(uint32_t(i));
  }

  // The light's edges, less what a shadow on the light's side covers.
  for (size_t k = 0; k < lightLines_; ++k) {
    const Line& line = lines_[k];
    const Vec2 sLow = glm::min(line.from, line.to), sHigh = glm::max(line.from, line.to);
    const double length = glm::length(line.to - line.from);
    covered_.clear();
    for (uint32_t j : active_) {
      Interval c;
      if (boxesApart(sLow, sHigh, low_[j], high_[j], eps)) continue;
      if (!clipToPolygon(k, firstLine_[j], firstLine_[j + 1] - firstLine_[j], true, false, c)) continue;
      covered_.push_back(c);
      occluded_ |= (c.to - c.from) * length > eps;
    }
    emitUncovered({0, 1, line.from, line.to}, false);
  }
  // Each shadow's edges inside the light, less what the other shadows cover.
  indexTwins(sharedEdges);
  lastHolder_ = kNoShadow;
  for (uint32_t i : active_)
    for (size_t e = firstLine_[i]; e < firstLine_[i + 1]; ++e) clipEdgeOfShadow(i, e);
}

namespace {

// The exact ends of a directed edge, -0 read as +0 (== holds them equal).
uint64_t edgeKey(const Vec2& from, const Vec2& to) {
  Fingerprint key;
  for (double x : {from.x, from.y, to.x, to.y}) key.add(x + 0.0);
  return key.value();
}

}  // namespace

void VisibleContour::indexTwins(bool sharedEdges) {
  twins_.clear();
  if (!sharedEdges || active_.size() < kTwinIndexFrom) return;
  size_t edges = 0;
  for (uint32_t i : active_) edges += firstLine_[i + 1] - firstLine_[i];
  twins_.assign(std::bit_ceil(2 * edges), Twin{});
  const size_t mask = twins_.size() - 1;
  for (uint32_t i : active_)
    for (uint32_t k = firstLine_[i]; k < firstLine_[i + 1]; ++k) {
      const Line& line = lines_[k];
      if (line.from == line.to) continue;
      size_t slot = edgeKey(line.from, line.to) & mask;
      while (twins_[slot].shadow != kNoShadow) slot = (slot + 1) & mask;
      twins_[slot] = {k, i};
    }
}

uint32_t VisibleContour::twinShadow(size_t edge) const {
  if (twins_.empty()) return kNoShadow;
  const Line& line = lines_[edge];
  const size_t mask = twins_.size() - 1;
  for (size_t slot = edgeKey(line.to, line.from) & mask; twins_[slot].shadow != kNoShadow; slot = (slot + 1) & mask) {
    const Line& other = lines_[twins_[slot].line];
    if (other.from == line.to && other.to == line.from) return twins_[slot].shadow;
  }
  return kNoShadow;
}

double VisibleContour::area() const {
  double sum = 0;
  for (const Segment2& s : boundary_) sum += cross2(s.from, s.to);
  return 0.5 * sum;
}

double VisibleContour::length() const {
  double sum = 0;
  for (const Segment2& s : boundary_) sum += glm::length(s.to - s.from);
  return sum;
}

bool VisibleContour::anyLeft(double eps) const {
  // Stretches shorter than eps alone are where crossings nearly meet, not a region.
  const bool anyStretch = std::any_of(boundary_.begin(), boundary_.end(), [&](const Segment2& s) {
    return glm::length(s.to - s.from) > eps;
  });
  return anyStretch && area() > 0;
}

}  // namespace penumbra
