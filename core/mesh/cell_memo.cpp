#include "core/mesh/cell_memo.h"

namespace penumbra {

namespace {

uint32_t lowWord(int64_t x) { return uint32_t(uint64_t(x)); }
uint32_t highWord(int64_t x) { return uint32_t(uint64_t(x) >> 32); }
int64_t fromWords(uint32_t low, uint32_t high) { return int64_t(uint64_t(high) << 32 | low); }

}  // namespace

void CellMemo::Output::clear() {
  pieces.clear();
  points.clear();
  triangles.clear();
  ownValues.clear();
}

CellMemo::CellMemo(uint64_t inputs, const Output& output)
    : inputs_(inputs), valid_(true), ownValues_(output.ownValues.begin(), output.ownValues.end()) {
  words_.reserve(1 + kPieceWords * output.pieces.size() + output.points.size() + 3 * output.triangles.size());
  words_.push_back(uint32_t(output.pieces.size()));
  for (const Piece& p : output.pieces)
    words_.insert(words_.end(), {lowWord(p.chunk.x), highWord(p.chunk.x), lowWord(p.chunk.y), highWord(p.chunk.y),
                                 p.pointsEnd, p.trianglesEnd});
  words_.insert(words_.end(), output.points.begin(), output.points.end());
  for (const auto& t : output.triangles) words_.insert(words_.end(), t.begin(), t.end());
}

CellMemo::Piece CellMemo::piece(size_t i) const {
  const uint32_t* w = &words_[1 + kPieceWords * i];
  return Piece{MeshChunkKey{fromWords(w[0], w[1]), fromWords(w[2], w[3])}, w[4], w[5]};
}

size_t CellMemo::pointCount() const {
  const size_t pieces = pieceCount();
  return pieces ? words_[1 + kPieceWords * (pieces - 1) + 4] : 0;
}

std::array<uint32_t, 3> CellMemo::triangle(size_t t) const {
  const uint32_t* w = &words_[1 + kPieceWords * pieceCount() + pointCount() + 3 * t];
  return {w[0], w[1], w[2]};
}

}  // namespace penumbra
