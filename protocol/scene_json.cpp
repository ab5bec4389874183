#include "protocol/scene_json.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/geom/polygon.h"
#include "core/geom/tolerance.h"
#include "core/scene/camera_limits.h"
#include "protocol/camera_json.h"
#include "protocol/json_reader.h"
#include "protocol/json_text.h"
#include "protocol/material_json.h"
#include "protocol/volume_json.h"

namespace penumbra::protocol {

namespace {

constexpr const char* kSceneFormat = "penumbra.scene";
constexpr int kSceneVersion = 1;

// "2.3e-03": planarity errors span many orders of magnitude.
std::string relativeError(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1e", value);
  return buffer;
}

// The checks every face and light polygon must pass, on its own vertices.
// `what` names the polygon in messages ("face", "light polygon").
void checkConvexPlanar(const Polygon3& polygon, const std::string& path, const std::string& what) {
  if (!planeOf(polygon))
    fail(path, what + " is degenerate (zero area or collinear vertices)");
  const double offPlane = planarityError(polygon);
  if (offPlane > kRelativePlanarity)
    fail(path, what + " is not planar (off by " + relativeError(offPlane) + " of its size)");
  if (!isConvex(polygon)) fail(path, what + " is not convex");
}

void checkPolygonSize(size_t count, const std::string& path, const std::string& what) {
  if (count < 3)
    fail(path, what + " needs at least 3 vertices, has " + std::to_string(count));
  if (count > kMaxPolygonVertices)
    fail(path, what + " has " + std::to_string(count) + " vertices, over the limit of " +
                   std::to_string(kMaxPolygonVertices));
}

// A point within ±kMaxCoordinate on every axis (`what` names it in the message).
Vec3 checkCoordinates(const Vec3& point, const std::string& path, const std::string& what) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(point[c]) <= kMaxCoordinate))
      fail(path, what + " coordinate " + shortNumber(point[c]) + " is beyond ±" +
                     shortNumber(kMaxCoordinate));
  return point;
}

// Each component's magnitude at most `most` (scale, rotation, radiance).
Vec3 checkMagnitude(const Vec3& value, const std::string& path, const std::string& what,
                    double most) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(value[c]) <= most))
      fail(path, what + " component " + shortNumber(value[c]) + " is beyond ±" + shortNumber(most));
  return value;
}

std::vector<Material> materialsFromJson(const Json& value, const std::string& path) {
  expectObject(value, path);
  std::vector<Material> materials;
  for (const auto& [name, body] : value.items()) {
    const std::string materialPath = keyPath(path, name);
    if (name.empty()) fail(materialPath, "material name is empty");
    Material material = materialFromJson(name, body, materialPath);
    materials.push_back(std::move(material));
  }
  return materials;
}

// Types here; every limit (finite, depth range, field of view, reach) in core's validateCamera, the
// one check the image route and the renderer use too.
Camera cameraFromJson(const Json& value, const std::string& path, const Bounds& sceneBounds) {
  expectObject(value, path);
  Camera camera;
  camera.position = expectVec3(requireKey(value, "position", path), keyPath(path, "position"));
  camera.target = expectVec3(requireKey(value, "target", path), keyPath(path, "target"));
  if (const Json* up = optionalKey(value, "up")) camera.up = expectVec3(*up, keyPath(path, "up"));
  if (const Json* projection = optionalKey(value, "projection")) {
    const std::string name = expectString(*projection, keyPath(path, "projection"));
    if (name == "perspective") camera.projection = Camera::Projection::Perspective;
    else if (name == "orthographic") camera.projection = Camera::Projection::Orthographic;
    else
      fail(keyPath(path, "projection"),
           "unknown projection '" + name + "' (expected perspective or orthographic)");
  }
  if (const Json* fov = optionalKey(value, "fov_y_deg"))
    camera.fovYDeg = expectNumber(*fov, keyPath(path, "fov_y_deg"));
  if (const Json* height = optionalKey(value, "height"))
    camera.height = expectNumber(*height, keyPath(path, "height"));
  if (const Json* near = optionalKey(value, "near")) camera.near = expectNumber(*near, keyPath(path, "near"));
  if (const Json* far = optionalKey(value, "far")) camera.far = expectNumber(*far, keyPath(path, "far"));
  try {
    validateCamera(camera, sceneBounds);
  } catch (const CameraError& error) {
    fail(keyPath(path, error.key()), error.problem());
  }
  return camera;
}

}  // namespace

Transform transformFromJson(const Json& value, const std::string& path) {
  expectObject(value, path);
  Transform transform;
  if (const Json* t = optionalKey(value, "translate"))
    transform.translate = checkCoordinates(expectVec3(*t, keyPath(path, "translate")),
                                           keyPath(path, "translate"), "translate");
  if (const Json* r = optionalKey(value, "rotate_deg"))
    transform.rotateDeg =
        checkMagnitude(expectVec3(*r, keyPath(path, "rotate_deg")), keyPath(path, "rotate_deg"),
                       "rotate_deg", kMaxRotationDeg);
  if (const Json* s = optionalKey(value, "scale")) {
    transform.scale = checkMagnitude(expectVec3(*s, keyPath(path, "scale")), keyPath(path, "scale"),
                                     "scale", kMaxScale);
    for (int c = 0; c < 3; ++c)
      if (transform.scale[c] == 0)
        fail(keyPath(path, "scale"), "scale component " + std::to_string(c) + " is zero");
  }
  return transform;
}

namespace {
// Per face, one normal per corner (smooth shading, SCENE_FORMAT.md): finite, non-zero.
std::vector<std::vector<Vec3>> cornerNormalsFromJson(const Json& value, const std::string& path,
                                                     const std::vector<std::vector<int>>& faces) {
  const Json& lists = expectArray(value, path);
  if (lists.size() != faces.size())
    fail(path, "has " + std::to_string(lists.size()) + " lists of corner normals for " +
                   std::to_string(faces.size()) + " faces");
  std::vector<std::vector<Vec3>> out(faces.size());
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::string facePath = indexPath(path, f);
    const Json& corners = expectArray(lists[f], facePath);
    if (corners.size() != faces[f].size())
      fail(facePath, "face has " + std::to_string(faces[f].size()) + " corners but " +
                         std::to_string(corners.size()) + " normals");
    for (size_t k = 0; k < corners.size(); ++k) {
      const Vec3 n = expectVec3(corners[k], indexPath(facePath, k));
      const double length = glm::length(n);
      if (!std::isfinite(length) || !(length > 1e-12))
        fail(indexPath(facePath, k), "a normal must be a finite, non-zero vector");
      out[f].push_back(n);
    }
  }
  return out;
}
}  // namespace

Object objectFromJson(const Json& value, const std::string& path, const std::vector<Material>& materials) {
  expectObject(value, path);
  Object object;
  object.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));

  const std::string verticesPath = keyPath(path, "vertices");
  const Json& vertices = expectArray(requireKey(value, "vertices", path), verticesPath);
  for (size_t i = 0; i < vertices.size(); ++i)
    object.vertices.push_back(checkCoordinates(expectVec3(vertices[i], indexPath(verticesPath, i)),
                                               indexPath(verticesPath, i), "vertex"));

  const std::string facesPath = keyPath(path, "faces");
  const Json& faces = expectArray(requireKey(value, "faces", path), facesPath);
  for (size_t f = 0; f < faces.size(); ++f) {
    const std::string facePath = indexPath(facesPath, f);
    const Json& face = expectArray(faces[f], facePath);
    checkPolygonSize(face.size(), facePath, "face");
    std::vector<int> indices;
    for (size_t k = 0; k < face.size(); ++k)
      indices.push_back(int(expectIndex(face[k], indexPath(facePath, k), object.vertices.size())));
    std::vector<int> sorted = indices;
    std::sort(sorted.begin(), sorted.end());
    if (const auto repeat = std::adjacent_find(sorted.begin(), sorted.end()); repeat != sorted.end())
      fail(facePath, "face repeats vertex " + std::to_string(*repeat));
    Polygon3 polygon;
    for (int index : indices) polygon.push_back(object.vertices[size_t(index)]);
    // Affine transforms keep planarity and convexity: check in object space.
    checkConvexPlanar(polygon, facePath, "face");
    object.faces.push_back(std::move(indices));
  }

  if (const Json* normals = optionalKey(value, "normals"))
    object.normals = cornerNormalsFromJson(*normals, keyPath(path, "normals"), object.faces);

  if (const Json* material = optionalKey(value, "material")) {
    object.material = expectString(*material, keyPath(path, "material"));
    const bool known = std::any_of(materials.begin(), materials.end(),
                                   [&](const Material& m) { return m.id == object.material; });
    if (!known) fail(keyPath(path, "material"), "unknown material '" + object.material + "'");
  }
  if (const Json* isStatic = optionalKey(value, "static"))
    object.isStatic = expectBool(*isStatic, keyPath(path, "static"));
  if (const Json* transform = optionalKey(value, "transform"))
    object.transform = transformFromJson(*transform, keyPath(path, "transform"));

  // An extreme non-uniform scale can flatten a face that was fine in object space, or place it
  // beyond the coordinate limit.
  const auto world = Scene::worldPolygons(object);
  for (size_t f = 0; f < world.size(); ++f) {
    for (const Vec3& p : world[f])
      checkCoordinates(p, indexPath(facesPath, f), "placed (world) vertex");
    if (!planeOf(world[f]))
      fail(indexPath(facesPath, f), "face becomes degenerate under the object's transform");
  }
  return object;
}

namespace {
// Reads just the id of a list entry so a duplicate is reported before anything
// else about that entry.
std::string peekId(const Json& value, const std::string& path) {
  expectObject(value, path);
  return expectName(requireKey(value, "id", path), keyPath(path, "id"));
}
}  // namespace

Polygon3 lightPolygonFromJson(const Json& value, const std::string& path) {
  const Json& polygon = expectArray(value, path);
  checkPolygonSize(polygon.size(), path, "light polygon");
  Polygon3 out;
  for (size_t i = 0; i < polygon.size(); ++i)
    out.push_back(checkCoordinates(expectVec3(polygon[i], indexPath(path, i)), indexPath(path, i),
                                   "light corner"));
  checkConvexPlanar(out, path, "light polygon");
  return out;
}

Vec3 radianceFromJson(const Json& value, const std::string& path) {
  const Vec3 radiance = expectVec3(value, path);
  for (int c = 0; c < 3; ++c)
    if (radiance[c] < 0) fail(path, "radiance is negative");
  return checkMagnitude(radiance, path, "radiance", kMaxRadiance);
}

Json polygonToJson(const Polygon3& polygon) {
  Json out = Json::array();
  for (const Vec3& v : polygon) out.push_back(toJson(v));
  return out;
}

Light lightFromJson(const Json& value, const std::string& path) {
  expectObject(value, path);
  Light light;
  light.id = expectName(requireKey(value, "id", path), keyPath(path, "id"));
  light.polygon = lightPolygonFromJson(requireKey(value, "polygon", path), keyPath(path, "polygon"));
  light.radiance = radianceFromJson(requireKey(value, "radiance", path), keyPath(path, "radiance"));
  return light;
}

Json lightToJson(const Light& light) {
  return Json{{"id", light.id}, {"polygon", polygonToJson(light.polygon)}, {"radiance", toJson(light.radiance)}};
}

Scene sceneFromJson(const Json& root, const VolumeFiles* volumeFiles) {
  expectHeader(root, kSceneFormat, kSceneVersion);

  const Json& lightsJson = expectArray(requireKey(root, "lights", ""), "lights");
  if (lightsJson.empty()) fail("lights", "at least one light is required");
  std::vector<Light> lights;
  std::set<std::string> lightIds;
  for (size_t i = 0; i < lightsJson.size(); ++i) {
    const std::string path = indexPath("lights", i);
    const std::string id = peekId(lightsJson[i], path);
    if (!lightIds.insert(id).second) fail(keyPath(path, "id"), "duplicate light id '" + id + "'");
    lights.push_back(lightFromJson(lightsJson[i], path));
  }

  std::vector<Material> materials;
  if (const Json* m = optionalKey(root, "materials")) materials = materialsFromJson(*m, "materials");

  const Json& objectsJson = expectArray(requireKey(root, "objects", ""), "objects");
  std::vector<Object> objects;
  std::vector<VolumeObject> volumes;
  std::set<std::string> objectIds;
  for (size_t i = 0; i < objectsJson.size(); ++i) {
    const std::string path = indexPath("objects", i);
    const std::string id = peekId(objectsJson[i], path);
    if (!objectIds.insert(id).second) fail(keyPath(path, "id"), "duplicate object id '" + id + "'");
    if (isVolumeObject(objectsJson[i], path))
      volumes.push_back(volumeFromJson(objectsJson[i], path, materials, volumeFiles));
    else
      objects.push_back(objectFromJson(objectsJson[i], path, materials));
  }

  std::optional<Camera> camera;
  if (const Json* c = optionalKey(root, "camera")) {
    // The camera's limits are relative to the scene's size and centre (camera_limits.h).
    Bounds bounds{lights[0].polygon[0], lights[0].polygon[0]};
    auto grow = [&](const Vec3& p) {
      bounds.min = glm::min(bounds.min, p);
      bounds.max = glm::max(bounds.max, p);
    };
    for (const Light& light : lights)
      for (const Vec3& p : light.polygon) grow(p);
    for (const Object& object : objects)
      for (const Vec3& p : object.vertices) grow(object.transform.apply(p));
    camera = cameraFromJson(*c, "camera", bounds);
  }

  try {
    return Scene(std::move(lights), std::move(materials), std::move(objects), std::move(camera),
                 std::move(volumes));
  } catch (const ValidationError&) {
    throw;
  } catch (const FaceError& e) {
    // A face the scene's tolerance cannot hold (too thin for the scene's size): only
    // known once every object has set the scene's size.
    throw ValidationError(indexPath(keyPath(indexPath("objects", e.objectIndex()), "faces"), e.face()),
                          e.problem());
  } catch (const std::invalid_argument& e) {
    // Validation above should make this unreachable; keep the error a refusal.
    throw ValidationError("", e.what());
  }
}

Json transformToJson(const Transform& transform) {
  return Json{{"translate", toJson(transform.translate)},
              {"rotate_deg", toJson(transform.rotateDeg)},
              {"scale", toJson(transform.scale)}};
}

Json objectToJson(const Object& object) {
  Json out = Json::object();
  out["id"] = object.id;
  Json vertices = Json::array();
  for (const Vec3& v : object.vertices) vertices.push_back(toJson(v));
  out["vertices"] = std::move(vertices);
  Json faces = Json::array();
  for (const auto& face : object.faces) faces.push_back(face);
  out["faces"] = std::move(faces);
  if (!object.normals.empty()) {
    Json normals = Json::array();
    for (const auto& corners : object.normals) {
      Json list = Json::array();
      for (const Vec3& n : corners) list.push_back(toJson(n));
      normals.push_back(std::move(list));
    }
    out["normals"] = std::move(normals);
  }
  if (!object.material.empty()) out["material"] = object.material;
  if (object.isStatic) out["static"] = true;
  if (object.transform != Transform{}) out["transform"] = transformToJson(object.transform);
  return out;
}

Json sceneToJson(const Scene& scene) {
  Json out = Json::object();
  out["format"] = kSceneFormat;
  out["version"] = kSceneVersion;

  Json lights = Json::array();
  for (const Light& light : scene.lights()) {
    lights.push_back(lightToJson(light));
  }
  out["lights"] = std::move(lights);

  Json materials = Json::object();
  for (const Material& material : scene.materials())
    materials[material.id] = materialToJson(material);
  out["materials"] = std::move(materials);

  Json objects = Json::array();
  for (const Object& object : scene.objects()) objects.push_back(objectToJson(object));
  for (const VolumeObject& volume : scene.volumes()) objects.push_back(volumeToJson(volume));
  out["objects"] = std::move(objects);

  if (const auto& camera = scene.camera()) out["camera"] = cameraToJson(*camera);
  return out;
}

Scene loadSceneFile(const std::string& path) {
  VolumeFiles files;
  files.baseDirectory = std::filesystem::path(path).parent_path().string();
  return sceneFromJson(parseJsonText(readTextFile(path, kMaxJsonFileBytes), kMaxJsonFileBytes, kMaxJsonDepth),
                       &files);
}

void saveSceneFile(const Scene& scene, const std::string& path) {
  writeTextFile(path, sceneToJson(scene).dump(2, ' ', false, Json::error_handler_t::replace) + "\n");
}

}  // namespace penumbra::protocol
