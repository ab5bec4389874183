#include "scenegen/scene_parts.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace penumbra {

namespace {
// Orders a planar polygon so it is counter-clockwise seen from `front`.
Polygon3 facing(Polygon3 polygon, const Vec3& front) {
  if (glm::dot(newellVector(polygon), front) < 0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}
}  // namespace

void addBox(Object& object, const Vec3& lo, const Vec3& hi) {
  const int first = int(object.vertices.size());
  for (int i = 0; i < 8; ++i)
    object.vertices.push_back(Vec3((i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y,
                                   (i & 4) ? hi.z : lo.z));
  const Vec3 centre = 0.5 * (lo + hi);
  for (int axis = 0; axis < 3; ++axis) {
    const int b = 1 << ((axis + 1) % 3), c = 1 << ((axis + 2) % 3), a = 1 << axis;
    for (int side = 0; side < 2; ++side) {
      const int s = side ? a : 0;
      std::vector<int> face{s, s | b, s | b | c, s | c};
      Polygon3 polygon;
      for (int& index : face) {
        index += first;
        polygon.push_back(object.vertices[index]);
      }
      if (glm::dot(newellVector(polygon), centroid(polygon) - centre) < 0)
        std::reverse(face.begin(), face.end());
      object.faces.push_back(face);
    }
  }
}

void addUvSphere(Object& object, const Vec3& centre, double radius, int stacks, int slices) {
  if (stacks < 2 || slices < 3) throw std::invalid_argument("addUvSphere: needs 2 stacks and 3 slices");
  const double pi = std::acos(-1.0);
  const int first = int(object.vertices.size());
  // Vertex first: the north pole, then rings 1..stacks-1 of `slices` vertices, then the south pole.
  object.vertices.push_back(centre + Vec3(0, radius, 0));
  for (int ring = 1; ring < stacks; ++ring) {
    const double theta = pi * ring / stacks;
    for (int j = 0; j < slices; ++j) {
      const double phi = 2 * pi * j / slices;
      object.vertices.push_back(centre + radius * Vec3(std::sin(theta) * std::cos(phi), std::cos(theta),
                                                       std::sin(theta) * std::sin(phi)));
    }
  }
  object.vertices.push_back(centre - Vec3(0, radius, 0));
  const int south = int(object.vertices.size()) - 1;
  auto at = [&](int ring, int j) { return first + 1 + (ring - 1) * slices + (j % slices); };
  auto outward = [&](std::vector<int> face) {
    Polygon3 polygon;
    for (int index : face) polygon.push_back(object.vertices[size_t(index)]);
    if (glm::dot(newellVector(polygon), centroid(polygon) - centre) < 0) std::reverse(face.begin(), face.end());
    object.faces.push_back(face);
  };
  for (int j = 0; j < slices; ++j) outward({first, at(1, j), at(1, j + 1)});
  for (int ring = 1; ring + 1 < stacks; ++ring)
    for (int j = 0; j < slices; ++j) outward({at(ring, j), at(ring + 1, j), at(ring + 1, j + 1), at(ring, j + 1)});
  for (int j = 0; j < slices; ++j) outward({south, at(stacks - 1, j + 1), at(stacks - 1, j)});
}

Object quadObject(const std::string& id, const Polygon3& quad, const Vec3& front) {
  Object object;
  object.id = id;
  object.vertices = facing(quad, front);
  object.faces = {{0, 1, 2, 3}};
  object.material = "white";
  object.isStatic = true;
  return object;
}

std::vector<Object> roomObjects(double x, double z, double y) {
  std::vector<Object> room;
  room.push_back(quadObject("floor", {{-x, 0, -z}, {x, 0, -z}, {x, 0, z}, {-x, 0, z}}, {0, 1, 0}));
  room.push_back(quadObject("ceiling", {{-x, y, -z}, {x, y, -z}, {x, y, z}, {-x, y, z}}, {0, -1, 0}));
  room.push_back(quadObject("wall_n", {{-x, 0, -z}, {x, 0, -z}, {x, y, -z}, {-x, y, -z}}, {0, 0, 1}));
  room.push_back(quadObject("wall_s", {{-x, 0, z}, {x, 0, z}, {x, y, z}, {-x, y, z}}, {0, 0, -1}));
  room.push_back(quadObject("wall_e", {{x, 0, -z}, {x, 0, z}, {x, y, z}, {x, y, -z}}, {-1, 0, 0}));
  room.push_back(quadObject("wall_w", {{-x, 0, -z}, {-x, 0, z}, {-x, y, z}, {-x, y, -z}}, {1, 0, 0}));
  return room;
}

Light squareCeilingLight(const std::string& id, const Vec3& centre, double side, double tiltDeg,
                         const Vec3& k) {
  const double h = side / 2;
  Polygon3 polygon{{-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}};
  const double angle = glm::radians(tiltDeg);
  for (Vec3& v : polygon) {
    // Rodrigues' rotation about a unit axis.
    v = v * std::cos(angle) + glm::cross(k, v) * std::sin(angle) +
        k * glm::dot(k, v) * (1 - std::cos(angle));
    v += centre;
  }
  Light light;
  light.id = id;
  light.polygon = facing(polygon, Vec3(0, -1, 0));
  light.radiance = Vec3(10.0);
  return light;
}

}  // namespace penumbra
