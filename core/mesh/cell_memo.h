// What one DM-tree cell handed the display mesh, kept between mesh calls: its pieces (lattice
// squares' parts of the cell) with their chunks, points and triangles, packed into one array of
// exact size, and a fingerprint of the inputs they came from. Plain value.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/geom/vec.h"
#include "core/illum/vertex_illumination.h"

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
// points, contact corners, centres) keep a copy: 4 bytes a point instead of 56 for most.
class CellMemo {
 public:
  // A point word with kOwnValue set indexes the own values; otherwise it is a VertexId's index,
  // with kDarkCorner set when the value leaves out the cell's dark lights (darkLights).
  static constexpr uint32_t kOwnValue = 0x80000000u, kDarkCorner = 0x40000000u;
  static constexpr uint32_t kIndexMask = 0x3fffffffu;
  // A lattice square's part of the cell: its chunk, and where its points and triangles end.
  struct Piece {
    MeshChunkKey chunk;
    uint32_t pointsEnd = 0, trianglesEnd = 0;
  };
  // A cell's output as it is emitted, before packing.
  struct Output {
    std::vector<Piece> pieces;
    std::vector<uint32_t> points;                    // builder calls in order, one word each
    std::vector<std::array<uint32_t, 3>> triangles;  // into points
    std::vector<std::pair<Vec2, VertexIrradiance>> ownValues;
    void clear();
  };

  CellMemo() = default;  // not valid: nothing emitted yet
  CellMemo(uint64_t inputs, const Output& output);

  bool valid() const { return valid_; }
  uint64_t inputs() const { return inputs_; }
  size_t pieceCount() const { return words_.empty() ? 0 : words_[0]; }
  Piece piece(size_t i) const;
  size_t pointCount() const;
  uint32_t point(size_t e) const { return words_[1 + kPieceWords * pieceCount() + e]; }
  std::array<uint32_t, 3> triangle(size_t t) const;
  const std::pair<Vec2, VertexIrradiance>& ownValue(uint32_t i) const { return ownValues_[i]; }

 private:
  static constexpr size_t kPieceWords = 6;  // chunk x and y (two words each), the two ends
  uint64_t inputs_ = 0;
  bool valid_ = false;
  // [piece count] [pieces] [points] [triangles, three words each]
  std::vector<uint32_t> words_;
  std::vector<std::pair<Vec2, VertexIrradiance>> ownValues_;
};

}  // namespace penumbra
