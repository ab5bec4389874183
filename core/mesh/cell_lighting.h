// What one DM-tree cell hands the display mesh: its pieces (lattice squares' parts of the
// cell), their points with values and their triangles, and a fingerprint of the inputs
// they come from. A CellLighter reads the scene and the receiver; one per thread, its
// buffers reused from cell to cell.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/dmtree/dm_tree.h"
#include "core/geom/plane_frame.h"
#include "core/illum/per_light_values.h"
#include "core/illum/vertex_illumination.h"
#include "core/mesh/cell_memo.h"
#include "core/mesh/cell_refinement.h"
#include "core/mesh/shared_point_values.h"

namespace penumbra {

// What meshing a receiver reads: its tree and its vertices' values (the engine's Receiver), and
// whether it is meshed from its lattice squares (then its vertices' values are not read:
// lattice_display_rule.h decides, the engine keeps the answer).
struct MeshSource {
  FaceId face;
  const PlaneFrame& frame;
  const DmTree& tree;
  const PerLightValues& perLight;  // [vertex][light]; unread when fromLattice
  bool fromLattice = false;
};

// dark[l]: the list holds an umbra entry of light l (its lights' values leave l out). Returns
// whether any light is dark.
bool darkLights(const OccluderList& list, std::vector<bool>& dark);
// A corner's value as the cell sees it when no face of its list passes through the corner.
VertexIrradiance cornerValue(const Scene& scene, const MeshSource& source, VertexId v,
                             const std::vector<bool>& dark, bool anyDark);

class CellLighter {
 public:
  // spacing: the lattice (0: none); chunkSide: a chunk's side (0: one chunk); refine: how far
  // each piece's triangles are refined (RefineSettings::tolerance 0: a fan each).
  // shared: values at points of cells' outlines kept for the neighbouring cells (null: none).
  CellLighter(const Scene& scene, const MeshSource& source, double spacing, double chunkSide,
              const RefineSettings& refine = {}, SharedPointValues* shared = nullptr);

  // Gathers cell c's inputs and returns their fingerprint.
  uint64_t gather(CellId c);
  // Triangulates the gathered cell (cut by the lattice) into `out`: valid, with the
  // fingerprint (see CellMemo for what it keeps). Vertices repeat once per side where the value jumps (contact edges,
  // cells in a light's umbra) through the values handed in.
  void emit(CellId c, CellMemo& out);
  // Refinement's test points of every emit() so far: values asked, points kept.
  size_t testPoints() const { return testPoints_; }
  size_t testPointsKept() const { return testPointsKept_; }

 private:
  // Appends the faces of the receiver's own mesh that meet its corners to listFaces_.
  void addOwnRing(uint32_t handle);
  // Whether a face of the gathered cell's list has its plane through p (listFaces_).
  bool onContact(const Vec3& p) const;
  // Whether q lies within eps of the gathered cell's outline (where a neighbour may ask too).
  bool onOutline(const Vec2& q) const;
  // Whether q lies within eps of a lattice line (where the cell's piece on the other side asks too).
  bool onLattice(const Vec2& q) const;
  // The value from each light of a point of the gathered cell's closure, as seen from the
  // cell (centre: its centroid), appended to output_.ownLights.
  void appendLightsAt(const Vec2& q, const OccluderList& list, const Vec3& centre) {
    lightsAt(q, list, centre, output_.ownLights);
  }
  void lightsAt(const Vec2& q, const OccluderList& list, const Vec3& centre, std::vector<VertexLight>& out);
  // Each light's unshadowed factor at q (0 where it does not reach): refinement's scale.
  void levelsAt(const Vec2& q, std::vector<double>& out) const;
  // Refines the piece whose points are output_.points[first, end) (its fan given) and, if it
  // added points, stores them and its triangles; returns the piece's fan word.
  CellFan refine(const Polygon2& piece, size_t first, CellFan fan, const OccluderList& list, const Vec3& centre);
  // An emitted point's per-light values (a corner's as gathered, or the copy kept).
  void pointLights(uint32_t word, std::vector<VertexLight>& out) const;
  MeshChunkKey chunkOf(const Polygon2& piece) const;

  // What a cell's triangles depend on, gathered for the cell being lit.
  struct Inputs {
    Polygon2 outline;                     // the cell's loop positions
    OccluderList occluders;               // its list
    // The listed faces' world polygons, concatenated; for a whole object (wholeObject()),
    // its transform's translation, rotation and scale.
    std::vector<Vec3> occluderPoints;
    // Their vertex counts (0: not in the scene, kWholeObjectSize: a whole object's transform).
    std::vector<uint32_t> occluderSizes;
    static constexpr uint32_t kWholeObjectSize = 0xffffffffu;
    // Per loop corner: 1 if lit from the cell (a face of its list through it), else 0 and its
    // value from each light (lights() entries a corner; the cell's dark lights in umbra).
    std::vector<uint8_t> cornerFromCell;
    std::vector<VertexLight> cornerLights;
    size_t lights = 0;
    std::vector<VertexId> corners;  // the loop's vertices (the output refers to them)
    void clear();
    uint64_t fingerprint() const;
  };

  const Scene& scene_;
  const MeshSource& source_;
  const double eps_, spacing_, chunkSide_;
  const RefineSettings refine_;
  SharedPointValues* shared_;
  PieceRefinement refinement_;
  size_t testPoints_ = 0, testPointsKept_ = 0;  // reused from piece to piece
  Inputs inputs_;
  uint64_t fingerprint_ = 0;
  std::vector<bool> dark_;
  bool anyDark_ = false;
  CellMemo::Output output_;  // the current cell's output before packing
  // The current cell's own values at lattice and contact points, by position: a lattice point
  // is a corner of up to four of its pieces and is kept once.
  std::vector<std::pair<Vec2, uint32_t>> ownAt_;
  // The gathered cell's listed faces, by entry (null: a whole object or not in the scene),
  // looked up once per cell rather than per point; and a one-cell list of lists for
  // illuminatePoint, reused.
  std::vector<const Face*> listFaces_;
  std::vector<const OccluderList*> oneCell_;
  const Face* face_ = nullptr;  // the receiver's face when it has corner normals
  Vec3 shadingAt(const Vec3& p) const;
};

}  // namespace penumbra
