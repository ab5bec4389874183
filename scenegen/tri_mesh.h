// An indexed triangle mesh for the procedural model generators (scenegen/*_mesh.h):
// welding by exact position, its edges, signed volume and placement in a room.
// Plain values and pure functions; thread-safe.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

// Triangles index `vertices`, counter-clockwise seen from outside (outward normals).
struct TriMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;
};

// Vertices at exactly equal positions made one (first occurrence kept, in order of
// first use), unused ones dropped, triangles with a repeated vertex dropped (the
// collapsed quads at Bézier poles and the like). Triangle order is kept.
TriMesh weldedMesh(const std::vector<Vec3>& positions,
                   const std::vector<std::array<int, 3>>& triangles);

// Edge use of a mesh: a directed edge (a, b) of a triangle is matched with its reverse
// (b, a). Closed: every directed edge once and its reverse once (watertight and
// consistently oriented).
struct MeshEdges {
  size_t edges = 0;       // undirected edges
  size_t boundary = 0;    // undirected edges used by one triangle
  size_t repeated = 0;    // directed edges used by more than one triangle (orientation breaks)
  size_t overShared = 0;  // undirected edges used by more than two triangles
  bool closed() const { return boundary == 0 && repeated == 0 && overShared == 0; }
  bool consistent() const { return repeated == 0; }
};
MeshEdges meshEdges(const TriMesh& mesh);

// Σ over triangles of det(a, b, c) / 6: the enclosed volume (positive when outward)
// for a closed mesh.
double signedVolume(const TriMesh& mesh);

// Reverses every triangle.
void flipTriangles(TriMesh& mesh);

struct MeshBounds {
  Vec3 min{0.0}, max{0.0};
  Vec3 size() const { return max - min; }
  Vec3 centre() const { return 0.5 * (min + max); }
};
MeshBounds meshBounds(const TriMesh& mesh);

// The mesh scaled by `scale` about its bounds' centre, then moved so that centre is at
// `at` — or, with `rest`, at (at.x, at.z) with the lowest vertex exactly at height at.y
// (y − min y is exact at the minimum). Welded again afterwards (a no-op unless rounding
// met two vertices). Throws std::invalid_argument for an empty mesh or scale ≤ 0.
TriMesh placedMesh(const TriMesh& mesh, double scale, const Vec3& at, bool rest);

// An object's faces as triangles in object space (fans; a fan's inner edges pair up within the
// face, so edge statistics are the polygons'), for the checks above.
TriMesh objectMesh(const Object& object);

// The mesh as one object of triangles ("clay" unless `material` is given).
Object meshObject(const std::string& id, const TriMesh& mesh, const std::string& material = "clay");

}  // namespace penumbra
