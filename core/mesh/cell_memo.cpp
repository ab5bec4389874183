#include "core/mesh/cell_memo.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

namespace penumbra {

namespace {

uint32_t lowWord(int64_t x) { return uint32_t(uint64_t(x)); }
uint32_t highWord(int64_t x) { return uint32_t(uint64_t(x) >> 32); }
int64_t fromWords(uint32_t low, uint32_t high) { return int64_t(uint64_t(high) << 32 | low); }

}  // namespace

// Own values are kept as their bytes.
static_assert(std::is_trivially_copyable_v<CellMemo::OwnValue> && sizeof(CellMemo::OwnValue) % sizeof(uint32_t) == 0);

void CellMemo::Output::clear() {
  pieces.clear();
  points.clear();
  ownValues.clear();
}

CellMemo::CellMemo(uint64_t inputs, const Output& output) : inputs_(inputs) {
  const size_t count = kHeaderWords + kPieceWords * output.pieces.size() + output.points.size() +
                       kOwnValueWords * output.ownValues.size();
  words_ = std::make_unique_for_overwrite<uint32_t[]>(count);
  uint32_t* w = words_.get();
  *w++ = uint32_t(output.pieces.size());
  *w++ = uint32_t(output.ownValues.size());
  for (const Piece& p : output.pieces) {
    const uint32_t piece[kPieceWords] = {lowWord(p.chunk.x),  highWord(p.chunk.x), lowWord(p.chunk.y),
                                         highWord(p.chunk.y), p.pointsEnd,         p.fan.apex};
    w = std::copy(piece, piece + kPieceWords, w);
  }
  w = std::copy(output.points.begin(), output.points.end(), w);
  if (!output.ownValues.empty()) std::memcpy(w, output.ownValues.data(), sizeof(OwnValue) * output.ownValues.size());
}

CellMemo::CellMemo(const CellMemo& other) : inputs_(other.inputs_) {
  if (!other.valid()) return;
  const size_t count = other.wordCount();
  words_ = std::make_unique_for_overwrite<uint32_t[]>(count);
  std::copy(other.words_.get(), other.words_.get() + count, words_.get());
}

CellMemo& CellMemo::operator=(const CellMemo& other) {
  if (this != &other) *this = CellMemo(other);
  return *this;
}

size_t CellMemo::wordCount() const {
  return kHeaderWords + kPieceWords * pieceCount() + pointCount() + kOwnValueWords * words_[1];
}

CellMemo::Piece CellMemo::piece(size_t i) const {
  const uint32_t* w = &words_[kHeaderWords + kPieceWords * i];
  return Piece{MeshChunkKey{fromWords(w[0], w[1]), fromWords(w[2], w[3])}, w[4], CellFan{w[5]}};
}

size_t CellMemo::pointCount() const {
  const size_t pieces = pieceCount();
  return pieces ? words_[kHeaderWords + kPieceWords * (pieces - 1) + 4] : 0;
}

CellMemo::OwnValue CellMemo::ownValue(uint32_t i) const {
  OwnValue value;
  const uint32_t* from = &words_[kHeaderWords + kPieceWords * pieceCount() + pointCount() + kOwnValueWords * i];
  std::memcpy(static_cast<void*>(&value), from, sizeof(OwnValue));
  return value;
}

}  // namespace penumbra
