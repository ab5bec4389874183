// What one DM-tree cell handed the display mesh, kept between mesh calls: its pieces (lattice
// squares' parts of the cell) with their chunks, points and fans, packed into one array of
// exact size, and a fingerprint of the inputs they came from. Plain value.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/geom/vec.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/cell_triangulation.h"

namespace penumbra {

// A display chunk: the lattice-aligned block (x, y) of a receiver's 2D frame.
struct MeshChunkKey {
  int64_t x = 0, y = 0;
  auto operator<=>(const MeshChunkKey&) const = default;
};

// The fingerprint covers the cell's outline and corner ids, occluder list, the listed faces'
// polygons and its corners' values (CellLighter::gather): an equal one means the cell would
// emit the same again (a 64-bit collision, ~2⁻⁶⁴ a compare, would keep a stale cell). Keeping
// the inputs themselves cost ~1.5 kB a cell, most of a dense room's memory.
//
// The points refer to the tree where they can: a corner whose value is its vertex's own, or its
// vertex's lights summed without those the cell is in umbra of, is kept as the VertexId; its
// position and value are read back from the MeshSource when a chunk is assembled (an unchanged
// fingerprint means both are the same bits). Only points with a value of their own (lattice
// points, contact corners, centres) keep a copy: 4 bytes a point instead of 56 for most. A
// piece's triangles are one fan (CellFan), kept as one word. The object is two words: millions
// of cells each hold one.
class CellMemo {
 public:
  // A point word with kOwnValue set indexes the own values; otherwise it is a VertexId's index,
  // with kDarkCorner set when the value leaves out the cell's dark lights (darkLights).
  static constexpr uint32_t kOwnValue = 0x80000000u, kDarkCorner = 0x40000000u;
  static constexpr uint32_t kIndexMask = 0x3fffffffu;
  // A point's own copy: where it is and its value (kept in 11 words: the position, irradiance
  // and class; `comparisons` is not kept, the display mesh does not show it).
  struct OwnValue {
    Vec2 at{0.0};
    VertexIrradiance value;
  };
  // A lattice square's part of the cell: its chunk, where its points end, and its fan over
  // them (the loop, then the centre point if the fan uses one).
  struct Piece {
    MeshChunkKey chunk;
    uint32_t pointsEnd = 0;
    CellFan fan;
  };
  // A cell's output as it is emitted, before packing.
  struct Output {
    std::vector<Piece> pieces;
    std::vector<uint32_t> points;  // builder calls in order, one word each
    std::vector<OwnValue> ownValues;
    void clear();
  };

  CellMemo() = default;  // not valid: nothing emitted yet
  CellMemo(uint64_t inputs, const Output& output);
  CellMemo(const CellMemo& other);
  CellMemo& operator=(const CellMemo& other);
  CellMemo(CellMemo&&) noexcept = default;
  CellMemo& operator=(CellMemo&&) noexcept = default;

  bool valid() const { return words_ != nullptr; }
  uint64_t inputs() const { return inputs_; }
  size_t pieceCount() const { return valid() ? words_[0] & ~kWideKeys : 0; }
  Piece piece(size_t i) const;
  size_t pointCount() const;
  uint32_t point(size_t e) const { return words_[pointsBegin() + e]; }
  OwnValue ownValue(uint32_t i) const;

 private:
  static constexpr size_t kHeaderWords = 2;  // piece count (| kWideKeys), own value count
  // A piece is its chunk's x and y, one word each (two if any of the cell's pieces needs them:
  // kWideKeys), then points end and fan.
  static constexpr uint32_t kWideKeys = 0x80000000u;
  static constexpr size_t kPieceWords = 4, kWidePieceWords = 6;
  static constexpr size_t kOwnValueWords = 11;
  size_t pieceWords() const { return words_[0] & kWideKeys ? kWidePieceWords : kPieceWords; }
  size_t pointsBegin() const { return kHeaderWords + pieceWords() * pieceCount(); }
  size_t wordCount() const;
  uint64_t inputs_ = 0;
  // [piece count] [own value count] [pieces] [points] [own values]; null: not valid
  std::unique_ptr<uint32_t[]> words_;
};

}  // namespace penumbra
