#include "core/mesh/cell_lighting.h"

#include <algorithm>
#include <cmath>
#include <span>

#include "core/illum/backprojection.h"
#include "core/illum/face_lookup.h"
#include "core/illum/light_sum.h"
#include "core/mesh/cell_triangulation.h"
#include "core/scene/mesh_topology.h"
#include "core/geom/fingerprint.h"
#include "core/mesh/lattice_split.h"

namespace penumbra {


bool darkLights(const OccluderList& list, std::vector<bool>& dark) {
  std::fill(dark.begin(), dark.end(), false);
  bool any = false;
  for (const OccluderEntry& entry : list)
    if (entry.umbra && entry.light < dark.size()) dark[entry.light] = any = true;
  return any;
}

VertexIrradiance cornerValue(const Scene& scene, const MeshSource& source, VertexId v,
                             const std::vector<bool>& dark, bool anyDark) {
  return sumLights(scene, source.perLight[v.index], anyDark ? &dark : nullptr);
}

void CellLighter::Inputs::clear() {
  outline.clear();
  occluders.clear();
  occluderPoints.clear();
  occluderSizes.clear();
  cornerFromCell.clear();
  cornerLights.clear();
  corners.clear();
}

uint64_t CellLighter::Inputs::fingerprint() const {
  Fingerprint f;
  f.addBytes(std::span<const Vec2>(outline));
  f.addBytes(std::span<const VertexId>(corners));
  f.add(uint64_t(occluders.size()));
  for (const OccluderEntry& e : occluders) addEntry(f, e);
  f.addBytes(std::span<const Vec3>(occluderPoints));
  f.addBytes(std::span<const uint32_t>(occluderSizes));
  f.addBytes(std::span<const uint8_t>(cornerFromCell));
  f.add(uint64_t(cornerLights.size()));
  for (const VertexLight& light : cornerLights) {
    f.add(light.factor());
    f.add(uint64_t(light.lightClass()) | uint64_t(light.applies()) << 8);
  }
  return f.value();
}

CellLighter::CellLighter(const Scene& scene, const MeshSource& source, double spacing,
                         double chunkSide, const RefineSettings& refine, SharedPointValues* shared)
    : scene_(scene),
      source_(source),
      eps_(scene.tolerance().length()),
      spacing_(spacing),
      chunkSide_(chunkSide),
      refine_(refine),
      shared_(shared),
      dark_(scene.lights().size()) {
  if (const Face* face = findFace(scene, source.face); face && !face->cornerNormals.empty()) face_ = face;
}

Vec3 CellLighter::shadingAt(const Vec3& p) const {
  return face_ ? interpolatedNormal(face_->polygon, face_->cornerNormals, source_.frame.normal, p)
               : source_.frame.normal;
}

// A point is on a value discontinuity (D0) when an occluder of a cell around it
// has its plane through it (it touches the receiver there): it then takes its
// value per side, as the limit from each cell whose list holds such a face (in a
// cell without one the value is continuous up to the point). "Through it" is the
// geometric predicate (length tolerance), not onPlane(): a point within onPlane() of
// the plane but off the contact line (e.g. on a line meeting it at a shallow angle
// near a footprint corner) lies inside one side, where the value is the point
// value (the face does not shadow it, SCENE_FORMAT.md), with no other side's
// copy to carry that value.
bool CellLighter::onContact(const Vec3& p) const {
  for (const Face* face : listFaces_)
    if (face && std::abs(face->plane.signedDistance(p)) <= eps_) return true;
  return false;
}

bool CellLighter::onOutline(const Vec2& q) const {
  const Polygon2& loop = inputs_.outline;
  for (size_t i = 0; i < loop.size(); ++i) {
    const Vec2 a = loop[i], d = loop[(i + 1) % loop.size()] - a;
    if (std::abs(cross2(d, q - a)) <= eps_ * glm::length(d)) return true;
  }
  return false;
}

bool CellLighter::onLattice(const Vec2& q) const {
  if (!(spacing_ > 0)) return false;
  const auto near = [&](double x) { return std::abs(x - std::round(x / spacing_) * spacing_) <= eps_; };
  return near(q.x) || near(q.y);
}

MeshChunkKey CellLighter::chunkOf(const Polygon2& piece) const {
  if (!(chunkSide_ > 0)) return MeshChunkKey{};
  const Vec2 middle = vertexAverage(piece);
  return MeshChunkKey{int64_t(std::floor(middle.x / chunkSide_)),
                      int64_t(std::floor(middle.y / chunkSide_))};
}

void CellLighter::addOwnRing(uint32_t handle) {
  const MeshTopology* mesh = scene_.meshTopology(handle);
  const std::span<const Face> faces = scene_.facesOfObject(handle);
  const uint32_t f = source_.face.face;
  if (!mesh || f + 1 >= mesh->welded.faceStarts.size()) return;
  for (uint32_t k = mesh->welded.faceStarts[f]; k < mesh->welded.faceStarts[f + 1]; ++k) {
    const uint32_t v = mesh->welded.corners[k];
    for (uint32_t j = mesh->vertexStarts[v]; j < mesh->vertexStarts[v + 1]; ++j)
      if (mesh->vertexFaces[j] != f) listFaces_.push_back(&faces[mesh->vertexFaces[j]]);
  }
}

uint64_t CellLighter::gather(CellId c) {
  const DmTree& tree = source_.tree;
  const HalfEdgeMesh& halfEdges = tree.mesh();
  const OccluderList& list = halfEdges.occluders(c);
  anyDark_ = darkLights(list, dark_);
  inputs_.clear();
  for (HalfEdgeId h : halfEdges.loop(c)) inputs_.corners.push_back(halfEdges.halfEdge(h).origin);
  for (VertexId v : inputs_.corners) inputs_.outline.push_back(tree.position(v));
  inputs_.occluders = list;
  listFaces_.clear();
  for (const OccluderEntry& entry : list) {
    const Face* face = findFace(scene_, entry.face);  // null: a whole object, or not in the scene
    listFaces_.push_back(face);
    if (isWholeObject(entry.face)) {
      // A mesh on its own face: the faces meeting the receiver's corners may pass through
      // a cell corner (where one in front of the receiver meets it), as listed faces do.
      if (entry.face.object == source_.face.object) addOwnRing(entry.face.object);
      // An object's faces are its authored ones placed by its transform: the transform
      // stands for all of them (a sphere's thousand faces need not be hashed per cell).
      const auto index = scene_.indexOfHandle(entry.face.object);
      inputs_.occluderSizes.push_back(index ? Inputs::kWholeObjectSize : 0);
      if (index) {
        const Transform& t = scene_.objects()[*index].transform;
        inputs_.occluderPoints.insert(inputs_.occluderPoints.end(), {t.translate, t.rotateDeg, t.scale});
      }
      continue;
    }
    inputs_.occluderSizes.push_back(face ? uint32_t(face->polygon.size()) : 0);
    if (face)
      inputs_.occluderPoints.insert(inputs_.occluderPoints.end(), face->polygon.begin(),
                                    face->polygon.end());
  }
  for (size_t i = 0; i < inputs_.corners.size(); ++i) {
    const VertexId v = inputs_.corners[i];
    // Only a face of this cell's list can hide light from the cell and not from the
    // corner (it passes through the corner); with none, the corner's value is the limit.
    const bool fromCell = onContact(source_.frame.to3D(inputs_.outline[i]));
    inputs_.cornerFromCell.push_back(fromCell ? 1 : 0);
    const std::span<const VertexLight> row = source_.perLight[v.index];
    for (size_t l = 0; l < row.size(); ++l) {
      VertexLight light = fromCell ? VertexLight{} : row[l];
      // A light the cell is in umbra of adds nothing there and darkens it (as sumLights' dark).
      if (!fromCell && anyDark_ && dark_[l] && light.applies()) {
        light.setFactor(0);
        light.setLightClass(LightClass::Umbra);
      }
      inputs_.cornerLights.push_back(light);
    }
  }
  inputs_.lights = source_.perLight.lightCount();
  fingerprint_ = inputs_.fingerprint();
  return fingerprint_;
}

// The value of a point of the cell's closure, as seen from the cell (centre: its centroid).
// emit() asks once per point of the cell (ownAt_), although a lattice point is a corner of
// up to four of its pieces.
void CellLighter::lightsAt(const Vec2& q, const OccluderList& list, const Vec3& centre,
                           std::vector<VertexLight>& out) {
  const Polygon2& polygon = inputs_.outline;
  const size_t lights = inputs_.lights;
  const size_t corner = size_t(std::find(polygon.begin(), polygon.end(), q) - polygon.begin());
  if (corner < polygon.size() && !inputs_.cornerFromCell[corner]) {
    const auto row = inputs_.cornerLights.begin() + long(corner * lights);
    out.insert(out.end(), row, row + long(lights));
    return;
  }
  const Vec3 p = source_.frame.to3D(q);
  const Vec3 normal = source_.frame.normal;
  const Vec3 shading = shadingAt(p);
  // A contact corner or lattice point takes the limit from the cell; another lattice
  // point is lit exactly from this cell's list (cases 2 and 3 keep it dark in a light's umbra).
  // (A refinement point at the centre itself has no direction to take a limit along: it lies
  // inside the cell, where the exact value is the limit.)
  const bool limit = (corner < polygon.size() || onContact(p)) && glm::length(centre - p) > eps_;
  // Lit from the list alone (no limit from this cell): a neighbour with the same list asks the
  // same of a point on their common edge, and so does the cell's piece across a lattice line.
  // (Which points are kept changes no value: the same q and list give the same bits.)
  const bool shareable = shared_ && !limit && (onOutline(q) || onLattice(q));
  if (shareable && shared_->find(q, &list, out)) return;
  const size_t first = out.size();
  oneCell_.assign(1, &list);
  for (size_t l = 0; l < lights; ++l)
    out.push_back(limit ? illuminateVertexFromCell(scene_, l, p, normal, shading, centre - p, list)
                        : illuminateVertex(scene_, l, p, normal, shading, oneCell_));
  if (shareable) shared_->keep(q, &list, std::span(out).subspan(first));
}

void CellLighter::levelsAt(const Vec2& q, std::vector<double>& out) const {
  thread_local Backprojection view;
  const Vec3 p = source_.frame.to3D(q);
  for (size_t l = 0; l < inputs_.lights; ++l) {
    view.reset(scene_, l, p, source_.frame.normal, shadingAt(p));
    out.push_back(view.applies() ? view.unoccludedFactor() : 0.0);
  }
}

void CellLighter::pointLights(uint32_t word, std::vector<VertexLight>& out) const {
  const size_t lights = inputs_.lights;
  size_t row = 0;
  const std::vector<VertexLight>* from = &output_.ownLights;
  if (word & CellMemo::kOwnValue) {
    row = word & CellMemo::kIndexMask;
  } else {
    const uint32_t index = word & CellMemo::kIndexMask;
    while (inputs_.corners[row].index != index) ++row;
    from = &inputs_.cornerLights;
  }
  out.insert(out.end(), from->begin() + long(row * lights), from->begin() + long((row + 1) * lights));
}

// The piece's fan (its points output_.points[first, end)) refined until interpolation is
// within the tolerance (cell_refinement.h); added points become own points of the cell, shared
// by position with its other pieces, and the triangles are listed.
CellFan CellLighter::refine(const Polygon2& piece, size_t first, CellFan fan, const OccluderList& list,
                            const Vec3& centre) {
  if (!(refine_.tolerance > 0) || narrowerThan(piece, refine_.minEdge)) return fan;
  PieceRefinement& r = refinement_;
  r.lights = inputs_.lights;
  r.points.clear(), r.values.clear(), r.levels.clear(), r.triangles.clear();
  r.capped = false;
  r.points.assign(piece.begin(), piece.end());
  if (fan.usesCentre()) r.points.push_back(output_.ownAt[output_.points.back() & CellMemo::kIndexMask]);
  for (size_t e = first; e < output_.points.size(); ++e) pointLights(output_.points[e], r.values);
  const uint32_t loop = uint32_t(piece.size());
  for (uint32_t t = 0; t < fan.triangleCount(loop); ++t) r.triangles.push_back(fan.triangle(loop, t));
  RefineSettings settings = refine_;
  settings.maxPoints = std::min(settings.maxPoints, CellMemo::kMaxPiecePoints);
  const size_t before = r.points.size();
  const bool added = refinePiece(
      r, settings, [&](const Vec2& q, std::vector<VertexLight>& values) { lightsAt(q, list, centre, values); },
      [&](const Vec2& q, std::vector<double>& levels) { levelsAt(q, levels); });
  output_.capped |= r.capped;
  testPoints_ += r.asked;
  testPointsKept_ += r.points.size() - before;
  if (!added) return fan;
  for (size_t i = before; i < r.points.size(); ++i) {
    const Vec2 q = r.points[i];
    const auto known = std::find_if(ownAt_.begin(), ownAt_.end(), [&](const auto& at) { return at.first == q; });
    if (known != ownAt_.end()) {
      output_.points.push_back(CellMemo::kOwnValue | known->second);
      continue;
    }
    ownAt_.push_back({q, uint32_t(output_.ownAt.size())});
    output_.points.push_back(CellMemo::kOwnValue | uint32_t(output_.ownAt.size()));
    output_.ownAt.push_back(q);
    const auto row = r.values.begin() + long(i * r.lights);
    output_.ownLights.insert(output_.ownLights.end(), row, row + long(r.lights));
  }
  for (const auto& t : r.triangles) output_.triangles.push_back(CellMemo::packTriangle(t));
  return CellFan::listedUpTo(uint32_t(output_.triangles.size()));
}

void CellLighter::emit(CellId c, CellMemo& out) {
  const OccluderList& list = source_.tree.mesh().occluders(c);
  const Polygon2& polygon = inputs_.outline;
  output_.clear();
  Vec3 centre{0.0};
  for (const Vec2& q : polygon) centre += source_.frame.to3D(q);
  centre /= double(polygon.size());
  ownAt_.clear();
  output_.lights = inputs_.lights;
  const auto addOwn = [&](const Vec2& q) {
    output_.points.push_back(CellMemo::kOwnValue | uint32_t(output_.ownAt.size()));
    output_.ownAt.push_back(q);
  };
  // A point is lit once and its copy shared by every piece it is a corner of.
  const auto addPoint = [&](const Vec2& q) {
    for (const auto& [at, index] : ownAt_)
      if (at == q) return output_.points.push_back(CellMemo::kOwnValue | index);
    ownAt_.push_back({q, uint32_t(output_.ownAt.size())});
    addOwn(q);
    appendLightsAt(q, list, centre);
  };
  for (const Polygon2& piece : splitByLattice(polygon, spacing_, eps_)) {
    for (const Vec2& q : piece) {
      // A corner whose value is its vertex's own is kept as the vertex (see CellMemo).
      const size_t corner = size_t(std::find(polygon.begin(), polygon.end(), q) - polygon.begin());
      const bool byVertex = corner < polygon.size() && !inputs_.cornerFromCell[corner] &&
                            inputs_.corners[corner].index <= CellMemo::kIndexMask;
      if (byVertex)
        output_.points.push_back(inputs_.corners[corner].index | (anyDark_ ? CellMemo::kDarkCorner : 0));
      else
        addPoint(q);
    }
    // The fan's indices are the piece's points in order: its loop, then the centre if used.
    const size_t first = output_.points.size() - piece.size();
    const CellFan fan = fanOfConvexCell(piece, eps_);
    if (fan.usesCentre()) {
      const Vec2 middle = vertexAverage(piece);
      oneCell_.assign(1, &list);
      addOwn(middle);
      const Vec3 p = source_.frame.to3D(middle);
      for (size_t l = 0; l < inputs_.lights; ++l)
        output_.ownLights.push_back(illuminateVertex(scene_, l, p, source_.frame.normal, shadingAt(p), oneCell_));
    }
    const CellFan shape = refine(piece, first, fan, list, centre);
    output_.pieces.push_back({chunkOf(piece), uint32_t(output_.points.size()), shape});
  }
  out = CellMemo(fingerprint_, output_);
}

}  // namespace penumbra
