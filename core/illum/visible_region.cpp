#include "core/illum/visible_region.h"

#include <algorithm>
#include <cmath>

namespace penumbra {

void VisibleRegion::closeNext(size_t begin) {
  if (nextPoints_.size() - begin < 3) {  // as subtract(): no area
    nextPoints_.resize(begin);
    return;
  }
  Piece piece;
  piece.begin = uint32_t(begin);
  piece.end = uint32_t(nextPoints_.size());
  piece.min = piece.max = nextPoints_[begin];
  for (size_t k = begin; k < nextPoints_.size(); ++k) {
    piece.min = glm::min(piece.min, nextPoints_[k]);
    piece.max = glm::max(piece.max, nextPoints_[k]);
  }
  nextPieces_.push_back(piece);
}

void VisibleRegion::appendNext(std::span<const Vec2> polygon) {
  const size_t begin = nextPoints_.size();
  nextPoints_.insert(nextPoints_.end(), polygon.begin(), polygon.end());
  closeNext(begin);
}

void VisibleRegion::reset(const Polygon2& initial) {
  nextPoints_.clear();
  nextPieces_.clear();
  appendNext(initial);
  std::swap(points_, nextPoints_);
  std::swap(pieces_, nextPieces_);
  if (!pieces_.empty()) {
    min_ = pieces_[0].min;
    max_ = pieces_[0].max;
  }
}

bool VisibleRegion::cutPiece(std::span<const Vec2> piece, const Polygon2& cutter, double eps) {
  const size_t pointMark = nextPoints_.size(), pieceMark = nextPieces_.size();
  rest_.assign(piece.begin(), piece.end());
  for (size_t i = 0; i < cutter.size(); ++i) {
    const Vec2 a = cutter[i], d = cutter[(i + 1) % cutter.size()] - a;
    const double length = glm::length(d);
    // splitConvex by the directed line: one classification, shared cut points.
    const size_t count = rest_.size();
    bool anyFront = false, anyBack = false;
    distance_.resize(count);
    for (size_t k = 0; k < count; ++k) {
      distance_[k] = cross2(d, rest_[k] - a) / length;
      anyFront |= distance_[k] > eps;
      anyBack |= distance_[k] < -eps;
    }
    if (!(length > 0) || count < 3 || !anyFront) {  // nothing left of an edge: no overlap
      nextPoints_.resize(pointMark);
      nextPieces_.resize(pieceMark);
      return false;
    }
    if (!anyBack) continue;  // wholly left of this edge
    left_.clear();
    const size_t rightBegin = nextPoints_.size();
    for (size_t k = 0; k < count; ++k) {
      const size_t j = (k + 1) % count;
      const int sk = distance_[k] > eps ? 1 : (distance_[k] < -eps ? -1 : 0);
      const int sj = distance_[j] > eps ? 1 : (distance_[j] < -eps ? -1 : 0);
      if (sk >= 0) left_.push_back(rest_[k]);
      if (sk <= 0) nextPoints_.push_back(rest_[k]);
      if (sk * sj < 0) {
        const double t = distance_[k] / (distance_[k] - distance_[j]);
        const Vec2 cut = rest_[k] + t * (rest_[j] - rest_[k]);
        left_.push_back(cut);
        nextPoints_.push_back(cut);
      }
    }
    closeNext(rightBegin);  // the right side, written in place, is a piece of its own
    std::swap(rest_, left_);
  }
  return true;
}

bool VisibleRegion::subtract(std::span<const Vec2> shadow, double eps) {
  if (pieces_.empty()) return false;
  // convex2d's withoutDuplicateVertices, into a reused buffer.
  Polygon2& cutter = cutter_;
  cutter.clear();
  for (const Vec2& v : shadow)
    if (cutter.empty() || glm::length(v - cutter.back()) > eps) cutter.push_back(v);
  while (cutter.size() > 1 && glm::length(cutter.front() - cutter.back()) <= eps) cutter.pop_back();
  if (cutter.size() < 3) return false;
  Vec2 low = cutter[0], high = cutter[0];
  for (const Vec2& v : cutter) {
    low = glm::min(low, v);
    high = glm::max(high, v);
  }
  if (boxesApart(min_, max_, low, high, eps)) return false;

  // Pieces the shadow cuts die in place and their remainders are appended; the
  // others are not touched (no copy per shadow of what it misses).
  bool removed = false;
  nextPoints_.clear();
  nextPieces_.clear();
  for (Piece& piece : pieces_) {
    const std::span<const Vec2> polygon(points_.data() + piece.begin, points_.data() + piece.end);
    if (boxesApart(piece.min, piece.max, low, high, eps) || !cutPiece(polygon, cutter, eps)) continue;
    piece.end = piece.begin;  // dead
    removed = true;
  }
  if (!removed) return false;
  std::erase_if(pieces_, [](const Piece& p) { return p.begin == p.end; });
  const uint32_t offset = uint32_t(points_.size());
  points_.insert(points_.end(), nextPoints_.begin(), nextPoints_.end());
  for (Piece piece : nextPieces_) {
    piece.begin += offset;
    piece.end += offset;
    pieces_.push_back(piece);
  }
  // Dead points are dropped once they outnumber the live ones.
  size_t live = 0;
  for (const Piece& piece : pieces_) live += piece.end - piece.begin;
  if (2 * live < points_.size()) {
    nextPoints_.clear();
    for (Piece& piece : pieces_) {
      const uint32_t begin = uint32_t(nextPoints_.size());
      nextPoints_.insert(nextPoints_.end(), points_.begin() + piece.begin, points_.begin() + piece.end);
      piece.begin = begin;
      piece.end = uint32_t(nextPoints_.size());
    }
    std::swap(points_, nextPoints_);
  }
  if (!pieces_.empty()) {
    min_ = pieces_[0].min;
    max_ = pieces_[0].max;
    for (const Piece& piece : pieces_) {
      min_ = glm::min(min_, piece.min);
      max_ = glm::max(max_, piece.max);
    }
  }
  return removed;
}

}  // namespace penumbra
