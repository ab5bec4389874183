#include "core/mesh/cell_memo.h"

#include <algorithm>
#include <climits>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>

namespace penumbra {

namespace {

uint32_t lowWord(uint64_t x) { return uint32_t(x); }
uint32_t highWord(uint64_t x) { return uint32_t(x >> 32); }
uint64_t fromWords(uint32_t low, uint32_t high) { return uint64_t(high) << 32 | low; }
bool fitsOneWord(int64_t x) { return x >= INT32_MIN && x <= INT32_MAX; }

uint32_t* putDouble(uint32_t* w, double x) {
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  *w++ = lowWord(bits);
  *w++ = highWord(bits);
  return w;
}
double getDouble(const uint32_t* w) {
  const uint64_t bits = fromWords(w[0], w[1]);
  double x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

}  // namespace

void CellMemo::Output::clear() {
  pieces.clear();
  points.clear();
  ownAt.clear();
  ownLights.clear();
  triangles.clear();
  capped = false;
}

CellMemo::CellMemo(uint64_t inputs, const Output& output) : inputs_(inputs) {
  const bool wide = std::any_of(output.pieces.begin(), output.pieces.end(), [](const Piece& p) {
    return !fitsOneWord(p.chunk.x) || !fitsOneWord(p.chunk.y);
  });
  if (output.pieces.size() >= kCapped) throw std::length_error("CellMemo: too many pieces in one cell");
  if (output.ownLights.size() != output.ownAt.size() * output.lights)
    throw std::invalid_argument("CellMemo: own values and lights disagree");
  const size_t count = kHeaderWords + (wide ? kWidePieceWords : kPieceWords) * output.pieces.size() +
                       output.points.size() + (kOwnAtWords + kLightWords * output.lights) * output.ownAt.size() +
                       output.triangles.size();
  words_ = std::make_unique_for_overwrite<uint32_t[]>(count);
  uint32_t* w = words_.get();
  *w++ = uint32_t(output.pieces.size()) | (wide ? kWideKeys : 0) | (output.capped ? kCapped : 0);
  *w++ = uint32_t(output.ownAt.size());
  *w++ = uint32_t(output.lights);
  for (const Piece& p : output.pieces) {
    const uint64_t x = uint64_t(p.chunk.x), y = uint64_t(p.chunk.y);
    if (wide) {
      *w++ = lowWord(x), *w++ = highWord(x), *w++ = lowWord(y), *w++ = highWord(y);
    } else {
      *w++ = lowWord(x), *w++ = lowWord(y);
    }
    *w++ = p.pointsEnd;
    *w++ = p.fan.apex;
  }
  w = std::copy(output.points.begin(), output.points.end(), w);
  for (size_t i = 0; i < output.ownAt.size(); ++i) {
    w = putDouble(putDouble(w, output.ownAt[i].x), output.ownAt[i].y);
    if (output.lights)  // no light: no copy (memcpy from a null pointer is undefined even for 0 bytes)
      std::memcpy(w, output.ownLights.data() + i * output.lights, sizeof(VertexLight) * output.lights);
    w += kLightWords * output.lights;
  }
  std::copy(output.triangles.begin(), output.triangles.end(), w);
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

size_t CellMemo::listedCount() const {
  size_t count = 0;
  for (size_t i = 0; i < pieceCount(); ++i)
    if (const CellFan fan = piece(i).fan; fan.listed()) count = fan.listedEnd();
  return count;
}

size_t CellMemo::wordCount() const { return trianglesBegin() + listedCount(); }

CellMemo::Piece CellMemo::piece(size_t i) const {
  const uint32_t* w = &words_[kHeaderWords + pieceWords() * i];
  if (words_[0] & kWideKeys)
    return Piece{MeshChunkKey{int64_t(fromWords(w[0], w[1])), int64_t(fromWords(w[2], w[3]))}, w[4], CellFan{w[5]}};
  return Piece{MeshChunkKey{int32_t(w[0]), int32_t(w[1])}, w[2], CellFan{w[3]}};
}

size_t CellMemo::pointCount() const {
  const size_t pieces = pieceCount();
  return pieces ? words_[kHeaderWords + pieceWords() * pieces - 2] : 0;  // the last piece's points end
}

Vec2 CellMemo::ownAt(uint32_t i) const {
  const uint32_t* w = &words_[pointsBegin() + pointCount() + ownValueWords() * i];
  return Vec2(getDouble(w), getDouble(w + 2));
}

void CellMemo::ownLights(uint32_t i, std::vector<VertexLight>& row) const {
  const uint32_t* w = &words_[pointsBegin() + pointCount() + ownValueWords() * i + kOwnAtWords];
  row.resize(lightCount());
  static_assert(std::is_trivially_copyable_v<VertexLight>);
  if (!row.empty()) std::memcpy(static_cast<void*>(row.data()), w, sizeof(VertexLight) * row.size());
}

}  // namespace penumbra
