#include "core/scene/scene.h"

#include <algorithm>
#include <stdexcept>

namespace penumbra {

Plane Light::plane() const {
  const auto p = planeOf(polygon);
  if (!p) throw std::invalid_argument("light '" + id + "' is degenerate");
  return *p;
}

Scene::Scene(std::vector<Light> lights, std::vector<Material> materials,
             std::vector<Object> objects, std::optional<Camera> camera)
    : lights_(std::move(lights)),
      materials_(std::move(materials)),
      objects_(std::move(objects)),
      camera_(std::move(camera)) {
  for (const Object& object : objects_) {
    if (!object.material.empty() && !findMaterial(object.material))
      throw std::invalid_argument("object '" + object.id + "' names unknown material '" +
                                  object.material + "'");
    for (const auto& face : object.faces)
      for (int index : face)
        if (index < 0 || size_t(index) >= object.vertices.size())
          throw std::invalid_argument("object '" + object.id + "' has a face index out of range");
  }
  deriveFaces();
}

std::vector<Polygon3> Scene::worldPolygons(const Object& object) {
  std::vector<Polygon3> out;
  out.reserve(object.faces.size());
  for (const auto& indices : object.faces) {
    Polygon3 polygon;
    polygon.reserve(indices.size());
    for (int index : indices) polygon.push_back(object.transform.apply(object.vertices[index]));
    if (object.transform.mirrors()) std::reverse(polygon.begin(), polygon.end());
    out.push_back(std::move(polygon));
  }
  return out;
}

void Scene::deriveFaces() {
  faces_.clear();
  bool first = true;
  auto grow = [&](const Vec3& p) {
    if (first) {
      bounds_ = Bounds{p, p};
      first = false;
    }
    bounds_.min = glm::min(bounds_.min, p);
    bounds_.max = glm::max(bounds_.max, p);
  };
  for (const Light& light : lights_)
    for (const Vec3& p : light.polygon) grow(p);
  for (uint32_t o = 0; o < objects_.size(); ++o) {
    const auto polygons = worldPolygons(objects_[o]);
    for (uint32_t f = 0; f < polygons.size(); ++f) {
      const auto plane = planeOf(polygons[f]);
      if (!plane)
        throw std::invalid_argument("object '" + objects_[o].id + "' face " + std::to_string(f) +
                                    " is degenerate");
      for (const Vec3& p : polygons[f]) grow(p);
      faces_.push_back(Face{FaceId{o, f}, polygons[f], *plane, area(polygons[f])});
    }
  }
  tolerance_ = Tolerance::forSize(bounds_.diagonal());
}

std::optional<size_t> Scene::findObject(std::string_view id) const {
  for (size_t i = 0; i < objects_.size(); ++i)
    if (objects_[i].id == id) return i;
  return std::nullopt;
}

std::optional<size_t> Scene::findMaterial(std::string_view id) const {
  for (size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].id == id) return i;
  return std::nullopt;
}

Vec3 Scene::albedo(FaceId face) const {
  const auto material = findMaterial(objects_.at(face.object).material);
  return material ? materials_[*material].albedo : Material{}.albedo;
}

FaceClass Scene::classify(const Face& face, const Light& light) const {
  const double eps = tolerance_.length();
  bool anyFront = false, anyBack = false;
  for (const Vec3& p : light.polygon) {
    const double d = face.plane.signedDistance(p);
    anyFront |= d > eps;
    anyBack |= d < -eps;
  }
  if (anyFront && anyBack) return FaceClass::Offending;
  return anyFront ? FaceClass::Front : FaceClass::Back;
}

bool Scene::receivesLight(const Face& face) const {
  return std::any_of(lights_.begin(), lights_.end(), [&](const Light& light) {
    return classify(face, light) != FaceClass::Back;
  });
}

}  // namespace penumbra
