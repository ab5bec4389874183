#include "interchange/light_polygons.h"

#include <algorithm>

namespace penumbra::interchange {

namespace {

Polygon3 pointsOf(const std::vector<Vec3>& positions, const IndexPolygon& face) {
  Polygon3 points;
  points.reserve(face.size());
  for (int i : face) points.push_back(positions[size_t(i)]);
  return points;
}

}  // namespace

std::vector<Polygon3> lightPolygons(const std::vector<Vec3>& positions, std::vector<IndexPolygon> faces,
                                    const std::optional<Vec3>& litCentre, ImportReport& report) {
  // Turn first, so triangles of one lamp wound differently in the file still join.
  std::vector<bool> turned(faces.size(), false);
  for (size_t k = 0; k < faces.size(); ++k) {
    const auto plane = planeOf(pointsOf(positions, faces[k]));
    if (litCentre && plane && plane->signedDistance(*litCentre) < 0) {
      std::reverse(faces[k].begin(), faces[k].end());
      turned[k] = true;
    }
  }
  // The same joiner that puts glTF's triangulated faces back together.
  std::vector<size_t> joinedInto;
  report.count("coplanar_light_triangles_joined", joinCoplanarConvex(positions, faces, &joinedInto));
  std::vector<bool> lightTurned(faces.size(), false);
  for (size_t k = 0; k < turned.size(); ++k)
    if (turned[k]) lightTurned[joinedInto[k]] = true;
  report.count("lights_turned_to_face_the_scene", size_t(std::count(lightTurned.begin(), lightTurned.end(), true)));

  std::vector<Polygon3> lights;
  lights.reserve(faces.size());
  for (const IndexPolygon& face : faces) lights.push_back(pointsOf(positions, face));
  return lights;
}

}  // namespace penumbra::interchange
