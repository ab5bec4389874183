#include "core/overlap/overlap_cube.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/geom/convex2d.h"
#include "core/overlap/penumbra_volume.h"

namespace penumbra {

namespace {

constexpr int kSides = 6;

// A cube side: the plane x[axis] = level, with 2D coordinates (column, row) in
// tile units along axes (axis+1)%3 and (axis+2)%3.
struct SideFrame {
  int axis = 0, uAxis = 1, vAxis = 2;
  double level = 0;
  Vec3 origin{0.0};  // 3D point of (0, 0)
  double tileSize = 1;

  static SideFrame of(int side, const Vec3& cubeMin, double cubeSide, int grid) {
    SideFrame f;
    f.axis = side / 2;
    f.uAxis = (f.axis + 1) % 3;
    f.vAxis = (f.axis + 2) % 3;
    f.origin = cubeMin;
    if (side % 2 == 1) f.origin[f.axis] += cubeSide;
    f.level = f.origin[f.axis];
    f.tileSize = cubeSide / grid;
    return f;
  }
  Vec3 to3D(const Vec2& q) const {
    Vec3 p = origin;
    p[uAxis] += q.x * tileSize;
    p[vAxis] += q.y * tileSize;
    return p;
  }
};

// Sutherland–Hodgman against one half-space, keeping f ≤ 0 (f = the outward
// plane's signed distance at the 3D point). Degenerate results (a point, a
// segment) are kept: a touching polygon still marks the tiles it touches.
Polygon2 clipInside(const Polygon2& polygon, const SideFrame& frame, const Plane& plane) {
  Polygon2 out;
  const size_t count = polygon.size();
  if (count == 0) return out;
  std::vector<double> f(count);
  bool anyOutside = false;
  for (size_t i = 0; i < count; ++i) {
    f[i] = plane.signedDistance(frame.to3D(polygon[i]));
    anyOutside |= f[i] > 0;
  }
  if (!anyOutside) return polygon;
  for (size_t i = 0; i < count; ++i) {
    const size_t j = (i + 1) % count;
    if (f[i] <= 0) out.push_back(polygon[i]);
    if ((f[i] < 0 && f[j] > 0) || (f[i] > 0 && f[j] < 0)) {
      const double t = f[i] / (f[i] - f[j]);
      out.push_back(polygon[i] + t * (polygon[j] - polygon[i]));
    }
  }
  return out;
}

struct Range {
  double min = INFINITY, max = -INFINITY;
  bool empty() const { return min > max; }
  void add(double x) {
    min = std::min(min, x);
    max = std::max(max, x);
  }
};

// The columns covered by a convex polygon within the closed row slab [y0, y1].
Range columnsInSlab(const Polygon2& polygon, double y0, double y1) {
  Range r;
  const size_t count = polygon.size();
  for (size_t i = 0; i < count; ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % count];
    if (a.y >= y0 && a.y <= y1) r.add(a.x);
    for (const double y : {y0, y1}) {
      if ((a.y < y && b.y > y) || (a.y > y && b.y < y)) {
        const double t = (y - a.y) / (b.y - a.y);
        r.add(a.x + t * (b.x - a.x));
      }
    }
  }
  return r;
}

// Tiles [first, last] (clamped to the grid) whose closed span [k, k+1] meets [min, max].
std::pair<int, int> touchedTiles(const Range& r, int grid) {
  const int first = std::max(0, static_cast<int>(std::ceil(r.min)) - 1);
  const int last = std::min(grid - 1, static_cast<int>(std::floor(r.max)));
  return {first, last};
}

std::string describe(FaceId f) {
  return "face (" + std::to_string(f.object) + ", " + std::to_string(f.face) + ")";
}

}  // namespace

int OverlapCube::gridForFaceCount(size_t faceCount) {
  const double g = std::ceil(kGridPerRootFace * std::sqrt(static_cast<double>(faceCount)));
  return static_cast<int>(std::clamp(g, static_cast<double>(kMinGrid), static_cast<double>(kMaxGrid)));
}

OverlapCube::Box OverlapCube::enclosingCube(const Scene& scene, const Polygon3& light,
                                            const OverlapCubeSettings& settings) {
  // Enclose the scene, the light and the edit volume.
  Bounds edit = settings.editVolume.value_or(Bounds{});
  if (!settings.editVolume) {
    const double margin = OverlapCubeSettings::kDefaultEditMargin * scene.bounds().diagonal();
    edit = Bounds{scene.bounds().min - Vec3(margin), scene.bounds().max + Vec3(margin)};
  }
  Vec3 lo = glm::min(scene.bounds().min, edit.min), hi = glm::max(scene.bounds().max, edit.max);
  for (const Vec3& p : light) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const Vec3 extent = hi - lo;
  Box box;
  box.side = std::max({extent.x, extent.y, extent.z, scene.tolerance().length()});
  box.min = 0.5 * (lo + hi) - Vec3(0.5 * box.side);
  return box;
}

OverlapCube::OverlapCube(const Scene& scene, size_t light, OverlapCubeSettings settings) {
  if (light >= scene.lights().size())
    throw std::invalid_argument("OverlapCube: light index out of range");
  if (settings.grid < 0) throw std::invalid_argument("OverlapCube: grid must be ≥ 0");
  light_ = scene.lights()[light].polygon;
  tolerance_ = scene.tolerance();
  grid_ = settings.grid > 0 ? settings.grid : gridForFaceCount(scene.faces().size());

  const Box box = enclosingCube(scene, light_, settings);
  cubeSide_ = box.side;
  cubeMin_ = box.min;

  facesInTile_ = std::vector<CompactIndexList>(static_cast<size_t>(kSides) * grid_ * grid_);
  for (const Face& face : scene.faces()) insertFace(face);
}

std::optional<std::vector<TileId>> OverlapCube::scanPenumbra(const Face& face) const {
  const std::optional<PenumbraVolume> volume =
      penumbraVolume(face.polygon, face.plane, light_, tolerance_);
  if (!volume) return std::nullopt;
  std::vector<TileId> tiles;
  const double g = grid_;
  for (int side = 0; side < kSides; ++side) {
    const SideFrame frame = SideFrame::of(side, cubeMin_, cubeSide_, grid_);
    // The side's square clipped by every half-space of the PSV.
    Polygon2 polygon{{0, 0}, {g, 0}, {g, g}, {0, g}};
    for (const Plane& plane : volume->bounds) {
      polygon = clipInside(polygon, frame, plane);
      if (polygon.empty()) break;
    }
    if (polygon.empty()) continue;
    Range rows;
    for (const Vec2& q : polygon) rows.add(q.y);
    const auto [firstRow, lastRow] = touchedTiles(rows, grid_);
    for (int row = firstRow; row <= lastRow; ++row) {
      const Range columns = columnsInSlab(polygon, row, row + 1);
      if (columns.empty()) continue;
      const auto [firstColumn, lastColumn] = touchedTiles(columns, grid_);
      for (int column = firstColumn; column <= lastColumn; ++column)
        tiles.push_back(TileId{static_cast<uint32_t>((side * grid_ + row) * grid_ + column)});
    }
  }
  return tiles;  // increasing by construction: side, row, column
}

bool OverlapCube::insertFace(const Face& face) {
  if (holds(face.id)) throw std::invalid_argument("OverlapCube: " + describe(face.id) + " is already held");
  // Soundness needs the face inside the cube (see the header): refuse, not guess.
  for (const Vec3& v : face.polygon) {
    const Vec3 rel = v - cubeMin_;
    if (glm::any(glm::lessThan(rel, Vec3(-tolerance_.length()))) ||
        glm::any(glm::greaterThan(rel, Vec3(cubeSide_ + tolerance_.length()))))
      throw std::invalid_argument("OverlapCube: " + describe(face.id) + " leaves the edit volume");
  }
  // A back face has no PSV: it neither casts nor receives for this light.
  std::optional<std::vector<TileId>> scanned = scanPenumbra(face);
  if (!scanned) return false;
  std::vector<TileId> tiles = std::move(*scanned);
  uint32_t slot;
  if (!freeSlots_.empty()) {
    slot = freeSlots_.back();
    freeSlots_.pop_back();
  } else {
    slot = static_cast<uint32_t>(slots_.size());
    slots_.emplace_back();
  }
  for (const TileId tile : tiles) facesInTile_[tile.value].push_back(slot);
  slots_[slot] = Slot{face.id, true, std::move(tiles)};
  slotOf_.emplace(face.id, slot);
  return true;
}

bool OverlapCube::removeFace(FaceId face) {
  const auto it = slotOf_.find(face);
  if (it == slotOf_.end()) return false;
  const uint32_t slot = it->second;
  for (const TileId tile : slots_[slot].tiles) {
    facesInTile_[tile.value].removeOne(slot);
  }
  slots_[slot] = Slot{};
  freeSlots_.push_back(slot);
  slotOf_.erase(it);
  return true;
}

std::vector<FaceId> OverlapCube::candidates(FaceId face) const {
  std::vector<FaceId> out;
  const auto it = slotOf_.find(face);
  if (it == slotOf_.end()) return out;
  const uint32_t self = it->second;
  std::vector<char> seen(slots_.size(), 0);
  seen[self] = 1;
  for (const TileId tile : slots_[self].tiles) {
    for (const uint32_t other : facesInTile_[tile.value]) {
      if (seen[other]) continue;
      seen[other] = 1;
      out.push_back(slots_[other].face);
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<FaceId, FaceId>> OverlapCube::candidatePairs() const {
  return candidatePairs([](uint32_t) { return false; });
}

std::vector<std::pair<FaceId, FaceId>> OverlapCube::candidatePairs(const std::function<bool(uint32_t)>& skipObject) const {
  std::vector<std::pair<FaceId, FaceId>> out;
  std::vector<uint8_t> skipped(slots_.size(), 0);
  uint32_t lastObject = 0xffffffffu;
  bool lastSkipped = false;
  for (uint32_t a = 0; a < slots_.size(); ++a) {
    if (!slots_[a].live) continue;
    if (slots_[a].face.object != lastObject) lastObject = slots_[a].face.object, lastSkipped = skipObject(lastObject);
    skipped[a] = lastSkipped;
  }
  // Per tile, its skipped objects' faces sorted by FaceId: a skipped face looks only at
  // those of later objects there, never at its own object's (the bulk of a big mesh's tiles).
  std::vector<uint32_t> skippedStart(facesInTile_.size() + 1, 0);
  std::vector<uint32_t> skippedFaces;
  for (size_t t = 0; t < facesInTile_.size(); ++t) {
    skippedStart[t] = uint32_t(skippedFaces.size());
    for (const uint32_t b : facesInTile_[t])
      if (skipped[b]) skippedFaces.push_back(b);
    std::sort(skippedFaces.begin() + skippedStart[t], skippedFaces.end(),
              [&](uint32_t x, uint32_t y) { return slots_[x].face < slots_[y].face; });
  }
  skippedStart.back() = uint32_t(skippedFaces.size());
  // mark[b] == a + 1: pair (a, b) already emitted while visiting a.
  std::vector<uint32_t> mark(slots_.size(), 0);
  for (uint32_t a = 0; a < slots_.size(); ++a) {
    if (!slots_[a].live) continue;
    const FaceId fa = slots_[a].face;
    for (const TileId tile : slots_[a].tiles) {
      if (!skipped[a]) {  // every face of the tile; a skipped partner's pair only from here
        for (const uint32_t b : facesInTile_[tile.value]) {
          const FaceId fb = slots_[b].face;
          if (mark[b] == a + 1 || b == a || (!skipped[b] && !(fa < fb))) continue;
          mark[b] = a + 1;
          out.emplace_back(std::min(fa, fb), std::max(fa, fb));
        }
        continue;
      }
      // Skipped faces of later objects in the tile.
      const auto first = skippedFaces.begin() + skippedStart[tile.value];
      const auto last = skippedFaces.begin() + skippedStart[tile.value + 1];
      for (auto it = std::upper_bound(first, last, fa.object,
                                      [&](uint32_t object, uint32_t b) { return object < slots_[b].face.object; });
           it != last; ++it) {
        const uint32_t b = *it;
        if (mark[b] == a + 1) continue;
        mark[b] = a + 1;
        out.emplace_back(fa, slots_[b].face);
      }
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<std::pair<FaceId, size_t>> OverlapCube::lowestSameObjectPartner(
    const std::function<bool(uint32_t)>& objects, const std::function<size_t(FaceId)>& rank) const {
  // Per tile and object: the two lowest ranks and the slot holding the lowest.
  struct Lowest {
    uint32_t object;
    size_t first, second;
    uint32_t firstSlot;
  };
  std::vector<size_t> slotRank(slots_.size(), SIZE_MAX);
  for (uint32_t a = 0; a < slots_.size(); ++a)
    if (slots_[a].live && objects(slots_[a].face.object)) slotRank[a] = rank(slots_[a].face);
  std::vector<uint32_t> tileStart(facesInTile_.size() + 1, 0);
  std::vector<Lowest> lowest;
  for (size_t t = 0; t < facesInTile_.size(); ++t) {
    tileStart[t] = uint32_t(lowest.size());
    for (const uint32_t b : facesInTile_[t]) {
      if (slotRank[b] == SIZE_MAX) continue;
      const uint32_t object = slots_[b].face.object;
      auto it = std::find_if(lowest.begin() + tileStart[t], lowest.end(), [&](const Lowest& l) { return l.object == object; });
      if (it == lowest.end()) {
        lowest.push_back({object, slotRank[b], SIZE_MAX, b});
      } else if (slotRank[b] < it->first) {
        it->second = it->first, it->first = slotRank[b], it->firstSlot = b;
      } else {
        it->second = std::min(it->second, slotRank[b]);
      }
    }
  }
  tileStart.back() = uint32_t(lowest.size());
  std::vector<std::pair<FaceId, size_t>> out;
  for (uint32_t a = 0; a < slots_.size(); ++a) {
    if (slotRank[a] == SIZE_MAX) continue;
    size_t best = SIZE_MAX;
    for (const TileId tile : slots_[a].tiles)
      for (uint32_t k = tileStart[tile.value]; k < tileStart[tile.value + 1]; ++k)
        if (lowest[k].object == slots_[a].face.object)
          best = std::min(best, lowest[k].firstSlot == a ? lowest[k].second : lowest[k].first);
    if (best != SIZE_MAX) out.emplace_back(slots_[a].face, best);
  }
  return out;
}

std::vector<TileId> OverlapCube::tilesOf(FaceId face) const {
  const auto it = slotOf_.find(face);
  return it == slotOf_.end() ? std::vector<TileId>{} : slots_[it->second].tiles;
}

std::vector<FaceId> OverlapCube::facesIn(TileId tile) const {
  std::vector<FaceId> out;
  if (tile.value >= facesInTile_.size()) return out;
  for (const uint32_t slot : facesInTile_[tile.value]) out.push_back(slots_[slot].face);
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<FaceId> OverlapCube::heldFaces() const {
  std::vector<FaceId> out;
  out.reserve(slotOf_.size());
  for (const auto& [face, slot] : slotOf_) out.push_back(face);
  return out;
}

OverlapCubeCounters OverlapCube::counters() const {
  OverlapCubeCounters c;
  c.tiles = facesInTile_.size();
  for (const auto& list : facesInTile_) c.occupiedTiles += list.empty() ? 0 : 1;
  c.faces = slotOf_.size();
  for (const Slot& slot : slots_) c.tileEntries += slot.tiles.size();
  c.meanTilesPerFace = c.faces ? static_cast<double>(c.tileEntries) / c.faces : 0;
  return c;
}

void OverlapCube::validate() const {
  auto fail = [](const std::string& what) { throw std::logic_error("OverlapCube: " + what); };
  if (grid_ <= 0 || facesInTile_.size() != static_cast<size_t>(kSides) * grid_ * grid_)
    fail("tile count is not 6·G²");
  // Id map ↔ live slots.
  size_t live = 0;
  for (uint32_t s = 0; s < slots_.size(); ++s) {
    if (!slots_[s].live) {
      if (!slots_[s].tiles.empty()) fail("dead slot " + std::to_string(s) + " keeps tiles");
      continue;
    }
    ++live;
    const auto it = slotOf_.find(slots_[s].face);
    if (it == slotOf_.end() || it->second != s) fail(describe(slots_[s].face) + ": id map disagrees");
  }
  if (live != slotOf_.size()) fail("id map size differs from live slots");
  if (live + freeSlots_.size() != slots_.size()) fail("free list does not match dead slots");
  for (const uint32_t s : freeSlots_)
    if (s >= slots_.size() || slots_[s].live) fail("free list names a live slot");
  // Face lists: sorted, unique, in range; each entry mirrored once in its tile.
  size_t faceEntries = 0;
  for (uint32_t s = 0; s < slots_.size(); ++s) {
    const auto& tiles = slots_[s].tiles;
    faceEntries += tiles.size();
    for (size_t i = 0; i < tiles.size(); ++i) {
      if (tiles[i].value >= facesInTile_.size()) fail(describe(slots_[s].face) + ": tile out of range");
      if (i > 0 && !(tiles[i - 1] < tiles[i])) fail(describe(slots_[s].face) + ": tiles not sorted/unique");
      const auto& list = facesInTile_[tiles[i].value];
      if (std::count(list.begin(), list.end(), s) != 1)
        fail(describe(slots_[s].face) + ": not listed exactly once in tile " + std::to_string(tiles[i].value));
    }
  }
  // Tile lists: every entry is a live slot listing that tile; totals agree, so
  // with the above the two sides are exact mirrors.
  size_t tileEntries = 0;
  for (uint32_t t = 0; t < facesInTile_.size(); ++t) {
    for (const uint32_t s : facesInTile_[t]) {
      ++tileEntries;
      if (s >= slots_.size() || !slots_[s].live) fail("tile " + std::to_string(t) + " lists a dead slot");
      if (!std::binary_search(slots_[s].tiles.begin(), slots_[s].tiles.end(), TileId{t}))
        fail("tile " + std::to_string(t) + " lists " + describe(slots_[s].face) + " which does not list it");
    }
  }
  if (tileEntries != faceEntries) fail("tile entries and face entries differ");
}

}  // namespace penumbra
