// Point queries on a lit Mesh: the irradiance at a point of a face, interpolated barycentrically
// in the triangle of that face's ReceiverMesh containing it (a uniform 2D grid per receiver finds
// it). Immutable after construction; queries are thread-safe. Borrows the Mesh: keep it alive.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "core/geom/plane_frame.h"
#include "core/mesh/mesh.h"
#include "core/scene/scene.h"

namespace penumbra {

class MeshLookup {
 public:
  // Receivers whose face is not in the scene are ignored.
  MeshLookup(const Scene& scene, const Mesh& mesh);

  // Irradiance at p (on face Scene::faces()[faceIndex]); nullopt when that face has no
  // receiver mesh (it receives no light). A point outside every triangle (an edge of the
  // face, float hit points) takes the value of the nearest triangle's closest point.
  std::optional<Vec3> irradiance(uint32_t faceIndex, const Vec3& p) const;

  bool hasReceiver(uint32_t faceIndex) const {
    return faceIndex < receiverOfFace_.size() && receiverOfFace_[faceIndex] >= 0;
  }

 private:
  struct Receiver {
    const ReceiverMesh* mesh = nullptr;
    PlaneFrame frame;
    std::vector<Vec2> points;  // positions in the frame
    Vec2 min{0.0};
    Vec2 cellSize{1.0};  // width, height of a grid cell
    int columns = 1, rows = 1;
    std::vector<uint32_t> cellStart;      // columns·rows + 1 offsets into cellTriangles
    std::vector<uint32_t> cellTriangles;  // triangles overlapping each cell
  };
  static Receiver buildReceiver(const ReceiverMesh& mesh);
  Vec3 interpolate(const Receiver& receiver, const Vec2& q) const;

  std::vector<Receiver> receivers_;
  std::vector<int32_t> receiverOfFace_;  // Scene::faces() index -> receivers_ index or -1
};

}  // namespace penumbra
