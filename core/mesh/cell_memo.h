// What one DM-tree cell handed the display mesh, kept between mesh calls: its pieces (lattice
// squares' parts of the cell) with their chunks, points and fans, packed into one array of
// exact size, and a fingerprint of the inputs they came from. Plain value.
#pragma once

#include <array>
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
// polygons and its corners' values from each light, radiance left out (CellLighter::gather): an equal one means the cell would
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
//
// A copy is each light's value (VertexLight, as the engine keeps a vertex's), not their sum:
// chunks sum them with the scene's radiances when they are assembled, so a new radiance
// changes no cell (issue 35: a light's power re-meshes nothing).
class CellMemo {
 public:
  // A point word with kOwnValue set indexes the own values; otherwise it is a VertexId's index,
  // with kDarkCorner set when the value leaves out the cell's dark lights (darkLights).
  static constexpr uint32_t kOwnValue = 0x80000000u, kDarkCorner = 0x40000000u;
  static constexpr uint32_t kIndexMask = 0x3fffffffu;
  // A listed triangle is one word: its three indices into its piece's points, 10 bits each.
  static constexpr uint32_t kMaxPiecePoints = 1024;
  static uint32_t packTriangle(const std::array<uint32_t, 3>& t) { return t[0] | t[1] << 10 | t[2] << 20; }
  static std::array<uint32_t, 3> unpackTriangle(uint32_t w) { return {w & 1023u, w >> 10 & 1023u, w >> 20 & 1023u}; }
  // A lattice square's part of the cell: its chunk, where its points end, and its fan over
  // them (the loop, then the centre point if the fan uses one), or, refined, where its
  // listed triangles end (CellFan::listed; its points: the loop, the centre if any, then the
  // added points).
  struct Piece {
    MeshChunkKey chunk;
    uint32_t pointsEnd = 0;
    CellFan fan;
  };
  // A cell's output as it is emitted, before packing: own point i is at ownAt[i] with the
  // values ownLights[i·lights, (i + 1)·lights).
  struct Output {
    std::vector<Piece> pieces;
    std::vector<uint32_t> points;  // builder calls in order, one word each
    std::vector<Vec2> ownAt;
    std::vector<VertexLight> ownLights;
    std::vector<uint32_t> triangles;  // refined pieces' triangles, packed (packTriangle)
    size_t lights = 0;
    bool capped = false;  // a piece's refinement stopped at kMaxPiecePoints short of the tolerance
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
  size_t pieceCount() const { return valid() ? words_[0] & ~(kWideKeys | kCapped) : 0; }
  Piece piece(size_t i) const;
  size_t pointCount() const;
  uint32_t point(size_t e) const { return words_[pointsBegin() + e]; }
  size_t lightCount() const { return valid() ? words_[2] : 0; }
  bool capped() const { return valid() && (words_[0] & kCapped) != 0; }
  // Listed triangle k of the cell (pieces in order: CellFan::listedEnd).
  std::array<uint32_t, 3> listedTriangle(size_t k) const { return unpackTriangle(words_[trianglesBegin() + k]); }
  Vec2 ownAt(uint32_t i) const;
  // Own point i's value from each light into `row` (resized to lightCount()).
  void ownLights(uint32_t i, std::vector<VertexLight>& row) const;

 private:
  static constexpr size_t kHeaderWords = 3;  // piece count (| kWideKeys), own value count, lights
  // A piece is its chunk's x and y, one word each (two if any of the cell's pieces needs them:
  // kWideKeys), then points end and fan.
  static constexpr uint32_t kWideKeys = 0x80000000u, kCapped = 0x40000000u;
  static constexpr size_t kPieceWords = 4, kWidePieceWords = 6;
  // An own value: its position (4 words), then 3 words a light.
  static constexpr size_t kOwnAtWords = 4, kLightWords = sizeof(VertexLight) / 4;
  size_t ownValueWords() const { return kOwnAtWords + kLightWords * words_[2]; }
  size_t pieceWords() const { return words_[0] & kWideKeys ? kWidePieceWords : kPieceWords; }
  size_t pointsBegin() const { return kHeaderWords + pieceWords() * pieceCount(); }
  size_t trianglesBegin() const { return pointsBegin() + pointCount() + ownValueWords() * words_[1]; }
  size_t listedCount() const;
  size_t wordCount() const;
  uint64_t inputs_ = 0;
  // [piece count] [own value count] [lights] [pieces] [points] [own values] [listed triangles];
  // null: not valid
  std::unique_ptr<uint32_t[]> words_;
};

}  // namespace penumbra
