#include "core/scene/scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/scene/closed_convex.h"
#include "core/scene/convex_solid.h"
#include "core/scene/mesh_topology.h"
#include "core/scene/shading_normal.h"

namespace penumbra {

namespace {

// Meshes with fewer faces cast face by face: cheap there, and the face-by-face contour's
// tolerance conventions (edges along each other) hold in the near-degenerate fixtures of
// small objects (a cube with a corner 1 µm off, coincident copies), where the chain's
// crossings were seen 2e-9 off (issue 35, open).
constexpr size_t kMinMeshFaces = 32;

// The object's solid if it is closed convex; else its mesh (object_shadow.h), unless it
// has fewer than kMinMeshFaces faces.
Scene::ObjectShape shapeOf(const Object& object, const std::vector<Face>& faces, const Tolerance& tolerance) {
  Scene::ObjectShape shape;
  if (isClosedConvex(object, faces, tolerance)) {
    shape.convex = std::make_shared<const ConvexSolid>(ConvexSolid::of(faces));
  } else if (faces.size() >= kMinMeshFaces) {
    shape.mesh = std::make_shared<MeshTopology>(MeshTopology::of(faces, tolerance.onPlane()));
  }
  return shape;
}

}  // namespace

Plane Light::plane() const {
  const auto p = planeOf(polygon);
  if (!p) throw std::invalid_argument("light '" + id + "' is degenerate");
  return *p;
}

Scene::Scene(std::vector<Light> lights, std::vector<Material> materials,
             std::vector<Object> objects, std::optional<Camera> camera,
             std::vector<VolumeObject> volumes)
    : lights_(std::move(lights)),
      materials_(std::move(materials)),
      objects_(std::move(objects)),
      camera_(std::move(camera)),
      volumes_(std::move(volumes)) {
  for (const Object& object : objects_) {
    handles_.push_back(nextHandle_++);
    checkReferences(object);
  }
  for (const VolumeObject& volume : volumes_) {
    if (!volume.data) throw std::invalid_argument("volume '" + volume.id + "' has no data");
    if (!volume.material.empty() && !findMaterial(volume.material))
      throw std::invalid_argument("volume '" + volume.id + "' names unknown material '" +
                                  volume.material + "'");
    if (findObject(volume.id))
      throw std::invalid_argument("duplicate object id '" + volume.id + "' (a volume's)");
  }
  deriveFaces();
}

void Scene::checkReferences(const Object& object) const {
  if (!object.material.empty() && !findMaterial(object.material))
    throw std::invalid_argument("object '" + object.id + "' names unknown material '" +
                                object.material + "'");
  for (const auto& face : object.faces)
    for (int index : face)
      if (index < 0 || size_t(index) >= object.vertices.size())
        throw std::invalid_argument("object '" + object.id + "' has a face index out of range");
  if (const auto problem = normalsProblem(object.normals, object.faces))
    throw std::invalid_argument("object '" + object.id + "' " + *problem);
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

std::optional<std::string> Scene::faceProblem(const Polygon3& world, const Tolerance& tolerance) {
  if (!planeOf(world)) return "face is degenerate (zero area or collinear vertices in world space)";
  const double w = width(world);
  if (!(w >= tolerance.minFaceWidth())) {
    char text[160];
    std::snprintf(text, sizeof text,
                  "face is thinner (%.2e m) than the minimum width %.2e m (1e-6 of the scene's diagonal)", w,
                  tolerance.minFaceWidth());
    return std::string(text);
  }
  return std::nullopt;
}

std::vector<Face> Scene::facesOf(const Object& object, uint32_t handle) const {
  checkReferences(object);
  std::vector<Face> out;
  const auto polygons = worldPolygons(object);
  for (uint32_t f = 0; f < polygons.size(); ++f) {
    if (const auto problem = faceProblem(polygons[f], tolerance_))
      throw FaceError(object.id, FaceError::kUnknown, f, *problem);
    // Snapped onto its plane: the format allows 1e-6 of the face's size off it, far
    // more than the length tolerance the ordering and clipping decide sides with.
    const Plane plane = *planeOf(polygons[f]);
    const bool off = std::any_of(polygons[f].begin(), polygons[f].end(), [&](const Vec3& p) {
      return std::abs(plane.signedDistance(p)) > tolerance_.snap();
    });
    Polygon3 polygon = off ? projectedOnto(polygons[f], plane) : polygons[f];
    const double faceArea = area(polygon);
    std::vector<Vec3> corners = worldCornerNormals(object.normals, f, object.transform, plane);
    out.push_back(Face{FaceId{handle, f}, std::move(polygon), plane, faceArea, std::move(corners)});
  }
  return out;
}

void Scene::deriveFaces() {
  // The scale first: faces are checked against the scene's tolerance.
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
  for (const Object& object : objects_)
    for (const auto& indices : object.faces)
      for (int index : indices) grow(object.transform.apply(object.vertices[size_t(index)]));
  tolerance_ = Tolerance::forSize(bounds_.diagonal());
  faces_.clear();
  solids_.clear();
  faceStarts_.assign(1, 0);
  for (size_t o = 0; o < objects_.size(); ++o) {
    try {
      std::vector<Face> faces = facesOf(objects_[o], handles_[o]);
      solids_.push_back(shapeOf(objects_[o], faces, tolerance_));
      for (Face& face : faces) faces_.push_back(std::move(face));
      faceStarts_.push_back(uint32_t(faces_.size()));
    } catch (const FaceError& error) {
      throw error.atObject(o);
    }
  }
}

void Scene::setHandles(std::vector<uint32_t> handles, uint32_t nextHandle) {
  if (handles.size() != objects_.size())
    throw std::invalid_argument(std::to_string(handles.size()) + " handles for " +
                                std::to_string(objects_.size()) + " objects");
  for (size_t o = 0; o < handles.size(); ++o)
    if ((o > 0 && handles[o] <= handles[o - 1]) || handles[o] >= nextHandle)
      throw std::invalid_argument("handles must increase and stay below the next one");
  handles_ = std::move(handles);
  nextHandle_ = nextHandle;
  deriveFaces();  // the faces' ids (and what is derived from them) name the handles
}

std::optional<size_t> Scene::indexOfHandle(uint32_t handle) const {
  const auto it = std::lower_bound(handles_.begin(), handles_.end(), handle);
  if (it == handles_.end() || *it != handle) return std::nullopt;
  return size_t(it - handles_.begin());
}

const Object& Scene::object(uint32_t handle) const {
  const auto index = indexOfHandle(handle);
  if (!index) throw std::out_of_range("no object with handle " + std::to_string(handle));
  return objects_[*index];
}

uint32_t Scene::addObject(Object object) {
  if (findObject(object.id) || findVolume(object.id))
    throw std::invalid_argument("duplicate object id '" + object.id + "'");
  const uint32_t handle = nextHandle_;
  std::vector<Face> faces = facesOf(object, handle);  // checks before changing anything
  ObjectShape solid = shapeOf(object, faces, tolerance_);
  ++nextHandle_;
  objects_.push_back(std::move(object));
  handles_.push_back(handle);
  solids_.push_back(std::move(solid));
  // Handles only grow: the new faces sort after every existing one.
  for (Face& face : faces) faces_.push_back(std::move(face));
  faceStarts_.push_back(uint32_t(faces_.size()));
  return handle;
}

void Scene::removeObject(uint32_t handle) {
  const auto index = indexOfHandle(handle);
  if (!index) throw std::invalid_argument("no object with handle " + std::to_string(handle));
  objects_.erase(objects_.begin() + long(*index));
  handles_.erase(handles_.begin() + long(*index));
  solids_.erase(solids_.begin() + long(*index));
  const uint32_t first = faceStarts_[*index], count = faceStarts_[*index + 1] - first;
  faces_.erase(faces_.begin() + first, faces_.begin() + first + count);
  faceStarts_.erase(faceStarts_.begin() + long(*index) + 1);
  for (size_t o = *index + 1; o < faceStarts_.size(); ++o) faceStarts_[o] -= count;
}

void Scene::setTransform(uint32_t handle, const Transform& transform) {
  const auto index = indexOfHandle(handle);
  if (!index) throw std::invalid_argument("no object with handle " + std::to_string(handle));
  Object moved = objects_[*index];
  moved.transform = transform;
  std::vector<Face> faces = facesOf(moved, handle);  // checks before changing anything
  if (faces.size() != faceStarts_[*index + 1] - faceStarts_[*index])
    throw std::logic_error("Scene::setTransform: a moved object changed its face count");
  // Closed and convex is affine-invariant, but the test is at the scene's tolerance in
  // world space: decided again, as a rebuild of the moved scene would.
  solids_[*index] = shapeOf(moved, faces, tolerance_);
  objects_[*index] = std::move(moved);
  for (size_t f = 0; f < faces.size(); ++f) faces_[faceStarts_[*index] + f] = std::move(faces[f]);
}

std::span<const Face> Scene::facesOfObject(uint32_t handle) const {
  const auto index = indexOfHandle(handle);
  if (!index) return {};
  return std::span<const Face>(faces_).subspan(faceStarts_[*index], faceStarts_[*index + 1] - faceStarts_[*index]);
}

const ConvexSolid* Scene::convexSolid(uint32_t handle) const {
  const auto index = indexOfHandle(handle);
  return index ? solids_[*index].convex.get() : nullptr;
}

const MeshTopology* Scene::meshTopology(uint32_t handle) const {
  const auto index = indexOfHandle(handle);
  return index ? solids_[*index].mesh.get() : nullptr;
}

std::optional<size_t> Scene::findObject(std::string_view id) const {
  for (size_t i = 0; i < objects_.size(); ++i)
    if (objects_[i].id == id) return i;
  return std::nullopt;
}

std::optional<size_t> Scene::findVolume(std::string_view id) const {
  for (size_t i = 0; i < volumes_.size(); ++i)
    if (volumes_[i].id == id) return i;
  return std::nullopt;
}

std::optional<size_t> Scene::findLight(std::string_view id) const {
  for (size_t i = 0; i < lights_.size(); ++i)
    if (lights_[i].id == id) return i;
  return std::nullopt;
}

std::optional<std::string> Scene::lightProblem(const Polygon3& polygon, const Tolerance& tolerance) {
  if (polygon.size() < 3) return "light polygon needs at least 3 vertices";
  for (const Vec3& p : polygon)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z)) return "light polygon has a non-finite vertex";
  if (!planeOf(polygon)) return "light polygon is degenerate (zero area or collinear vertices)";
  if (planarityError(polygon) > kRelativePlanarity) return "light polygon is not planar";
  if (!isConvex(polygon)) return "light polygon is not convex";
  // As thin as a face the scene refuses: its shadows' critical lines would coincide.
  const double w = width(polygon);
  if (!(w >= tolerance.minFaceWidth())) {
    char text[160];
    std::snprintf(text, sizeof text, "light polygon is thinner (%.2e m) than the minimum width %.2e m", w,
                  tolerance.minFaceWidth());
    return std::string(text);
  }
  return std::nullopt;
}

std::optional<std::string> Scene::radianceProblem(const Vec3& radiance) {
  for (int c = 0; c < 3; ++c) {
    if (!std::isfinite(radiance[c])) return "radiance is not finite";
    if (radiance[c] < 0) return "radiance is negative";
  }
  return std::nullopt;
}

void Scene::setMaterial(Material material) {
  if (const auto index = findMaterial(material.id))
    materials_[*index] = std::move(material);
  else
    materials_.push_back(std::move(material));
}

void Scene::setLight(size_t index, const Polygon3& polygon, const Vec3& radiance) {
  if (index >= lights_.size()) throw std::invalid_argument("no light with index " + std::to_string(index));
  // A kept polygon is not checked again: a loaded scene's lights passed the file's checks,
  // and a radiance edit must not fail on a rule (minFaceWidth) those did not apply.
  if (polygon != lights_[index].polygon)
    if (const auto problem = lightProblem(polygon, tolerance_))
      throw std::invalid_argument("light '" + lights_[index].id + "': " + *problem);
  if (const auto problem = radianceProblem(radiance))
    throw std::invalid_argument("light '" + lights_[index].id + "': " + *problem);
  lights_[index].polygon = polygon;
  lights_[index].radiance = radiance;
}

void Scene::addLight(Light light) {
  if (findLight(light.id)) throw std::invalid_argument("duplicate light id '" + light.id + "'");
  if (const auto problem = lightProblem(light.polygon, tolerance_))
    throw std::invalid_argument("light '" + light.id + "': " + *problem);
  if (const auto problem = radianceProblem(light.radiance))
    throw std::invalid_argument("light '" + light.id + "': " + *problem);
  lights_.push_back(std::move(light));
}

void Scene::removeLight(size_t index) {
  if (index >= lights_.size()) throw std::invalid_argument("no light with index " + std::to_string(index));
  if (lights_.size() == 1)
    throw std::invalid_argument("light '" + lights_[index].id + "' is the scene's last light");
  lights_.erase(lights_.begin() + std::ptrdiff_t(index));
}

std::optional<size_t> Scene::findMaterial(std::string_view id) const {
  for (size_t i = 0; i < materials_.size(); ++i)
    if (materials_[i].id == id) return i;
  return std::nullopt;
}

Vec3 Scene::albedo(FaceId face) const {
  const auto material = findMaterial(object(face.object).material);
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
