// OverlapCube: the shadow overlap cube of one light (paper §2.2) — per-face tile
// lists and per-tile face lists of PSV(face) ∩ cube sides. Single writer; const use is thread-safe.
#pragma once

#include <compare>
#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <utility>
#include <functional>
#include <vector>

#include "core/geom/polygon.h"
#include "core/overlap/compact_index_list.h"
#include "core/geom/tolerance.h"
#include "core/scene/scene.h"

namespace penumbra {

// A tile of one cube side: (side · G + row) · G + column; sides are −x, +x, −y,
// +y, −z, +z; a side's columns run along the next axis, rows along the one after.
struct TileId {
  static constexpr uint32_t kInvalid = UINT32_MAX;
  uint32_t value = kInvalid;
  bool isValid() const { return value != kInvalid; }
  bool operator==(const TileId&) const = default;
  auto operator<=>(const TileId&) const = default;
};

struct OverlapCubeSettings {
  // Tiles per side edge (G); 0 = OverlapCube::gridForFaceCount(scene faces).
  int grid = 0;
  // The space objects may move in; nullopt = the scene bounds grown by
  // kDefaultEditMargin of the scene diagonal on every side.
  std::optional<Bounds> editVolume;
  static constexpr double kDefaultEditMargin = 0.05;
};

struct OverlapCubeCounters {
  size_t tiles = 0;          // 6·G²
  size_t occupiedTiles = 0;  // tiles holding at least one face
  size_t faces = 0;          // faces held (front or offending for the light)
  size_t tileEntries = 0;    // Σ tiles per face
  double meanTilesPerFace = 0;
};

// Soundness (why candidates() never misses a shadow relation): if occluder O
// shadows receiver R, some segment from a light point s (strictly in front of
// both planes: in front of O to be blocked by it, in front of R to light it)
// passes through o ∈ O and then reaches r ∈ R. Extend it beyond r until it
// leaves the cube at x (the cube encloses the light and the edit volume, so s,
// o, r are inside it). The segment s→x passes through O and x lies behind O's
// plane, so x ∈ PSV(O); likewise it passes through R with x behind R's plane, so
// x ∈ PSV(R). x lies on some side, and the side polygons are that side's square
// ∩ each PSV, so both polygons contain x — with a margin of onPlane(), since
// the PSV half-spaces are widened by it. Scan conversion marks every tile the
// closed polygon touches, so the tile(s) holding x list both O and R.
class OverlapCube {
 public:
  // Builds the cube for `light` and inserts every face of the scene that is
  // front or offending for it. Throws std::invalid_argument for a bad light
  // index or a negative grid.
  OverlapCube(const Scene& scene, size_t light, OverlapCubeSettings settings = {});

  // The rule for grid = 0: G = clamp(ceil(kGridPerRootFace · √faces), kMinGrid,
  // kMaxGrid), so 6·G² grows in step with the face count.
  static constexpr double kGridPerRootFace = 2.0;
  static constexpr int kMinGrid = 8;
  static constexpr int kMaxGrid = 256;
  static int gridForFaceCount(size_t faceCount);

  // The cube a light's OverlapCube spans (min corner, side): it encloses the scene's
  // bounds, the edit volume and the light polygon. A face must lie in it to be inserted.
  struct Box {
    Vec3 min{0.0};
    double side = 0;
  };
  static Box enclosingCube(const Scene& scene, const Polygon3& light, const OverlapCubeSettings& settings = {});

  // Scan-converts PSV(face) into the tiles. Returns false (and stores nothing)
  // for a back face of this light. Throws std::invalid_argument if the face is
  // already held or reaches outside the cube (the edit volume was too small).
  bool insertFace(const Face& face);
  // Removes the face using its stored tile list; false if it is not held.
  bool removeFace(FaceId face);
  bool holds(FaceId face) const { return slotOf_.count(face) != 0; }

  // Faces sharing at least one tile with `face` (not itself), sorted, each once.
  // Empty if the face is not held.
  std::vector<FaceId> candidates(FaceId face) const;
  // Every unordered pair of held faces sharing a tile, as (smaller, larger),
  // sorted, each once.
  std::vector<std::pair<FaceId, FaceId>> candidatePairs() const;
  // The same without the pairs of two faces of one object that `skipObject` names (a mesh
  // casting whole on its own faces: a 6,000-face model has millions of them).
  std::vector<std::pair<FaceId, FaceId>> candidatePairs(const std::function<bool(uint32_t)>& skipObject) const;
  // For each face of an object `objects` names that shares a tile with another face of
  // its object: the lowest `rank` among those others. O(faces' tiles), not O(pairs).
  std::vector<std::pair<FaceId, size_t>> lowestSameObjectPartner(const std::function<bool(uint32_t)>& objects,
                                                                 const std::function<size_t(FaceId)>& rank) const;

  // A held face's tiles, sorted; empty if not held.
  std::vector<TileId> tilesOf(FaceId face) const;
  // The faces in a tile, sorted.
  std::vector<FaceId> facesIn(TileId tile) const;
  std::vector<FaceId> heldFaces() const;  // sorted

  int grid() const { return grid_; }
  Vec3 cubeMin() const { return cubeMin_; }
  double cubeSide() const { return cubeSide_; }
  size_t tileCount() const { return facesInTile_.size(); }
  OverlapCubeCounters counters() const;

  // Throws std::logic_error unless the per-face and per-tile lists mirror each
  // other exactly, hold no duplicates and no dead slots, and the id map agrees.
  void validate() const;

 private:
  struct Slot {
    FaceId face;
    bool live = false;
    std::vector<TileId> tiles;  // sorted, unique
  };

  // The face's tiles, sorted; nullopt for a back face (no PSV).
  std::optional<std::vector<TileId>> scanPenumbra(const Face& face) const;

  Polygon3 light_;
  Tolerance tolerance_;
  int grid_ = 0;
  Vec3 cubeMin_{0.0};
  double cubeSide_ = 0;
  std::vector<Slot> slots_;
  std::vector<uint32_t> freeSlots_;
  std::map<FaceId, uint32_t> slotOf_;
  std::vector<CompactIndexList> facesInTile_;  // slot indices, unordered
};

}  // namespace penumbra
