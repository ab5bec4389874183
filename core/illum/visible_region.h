// The visible part of a light in its plane's 2D frame: disjoint convex pieces
// stored flat, with bounding boxes, cut by convex shadows in place. Buffers are
// reused from cut to cut (no allocation per piece). Owned by one thread.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/geom/convex2d.h"

namespace penumbra {

class VisibleRegion {
 public:
  // One convex CCW piece, nothing removed yet.
  void reset(const Polygon2& initial);

  // Removes a convex CCW shadow from every piece (convex2d's subtract, piece by
  // piece: peel off the part outside each shadow edge in turn; a piece whose
  // overlap with the shadow has no positive area at eps stays whole). Returns
  // whether some piece lost positive area.
  bool subtract(std::span<const Vec2> shadow, double eps);

  bool empty() const { return pieces_.empty(); }
  size_t pieceCount() const { return pieces_.size(); }
  std::span<const Vec2> piece(size_t i) const {
    return {points_.data() + pieces_[i].begin, points_.data() + pieces_[i].end};
  }

 private:
  struct Piece {
    uint32_t begin = 0, end = 0;
    Vec2 min{0.0}, max{0.0};
  };
  // Cuts one piece by the cleaned cutter into next*; false (nothing written) if
  // their overlap has no positive area.
  bool cutPiece(std::span<const Vec2> piece, const Polygon2& cutter, double eps);
  void appendNext(std::span<const Vec2> polygon);
  void closeNext(size_t begin);  // nextPoints_ from begin on as one piece

  std::vector<Vec2> points_, nextPoints_;
  std::vector<Piece> pieces_, nextPieces_;
  Vec2 min_{0.0}, max_{0.0};  // all pieces' bounding box
  Polygon2 rest_, left_;      // scratch of cutPiece
  Polygon2 cutter_;           // the shadow without duplicate vertices
  std::vector<double> distance_;
};

}  // namespace penumbra
