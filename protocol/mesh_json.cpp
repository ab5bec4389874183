#include "protocol/mesh_json.h"

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <ostream>
#include <stdexcept>

#include "core/geom/tolerance.h"
#include "protocol/json_reader.h"
#include "protocol/json_text.h"

namespace penumbra::protocol {

namespace {

constexpr const char* kMeshFormat = "penumbra.mesh";
constexpr int kMeshVersion = 1;

LightClass lightClassFromJson(const Json& value, const std::string& path) {
  const std::string name = expectString(value, path);
  for (LightClass c : {LightClass::Lit, LightClass::Penumbra, LightClass::Umbra})
    if (name == toString(c)) return c;
  fail(path, "unknown class '" + name + "' (expected lit, penumbra or umbra)");
}

// An array whose length must match the positions'.
const Json& perVertexArray(const Json& receiver, const char* key, const std::string& path, size_t count) {
  const std::string arrayPath = keyPath(path, key);
  const Json& array = expectArray(requireKey(receiver, key, path), arrayPath);
  if (array.size() != count)
    fail(arrayPath, std::string(key) + " has " + std::to_string(array.size()) +
                        " entries, positions has " + std::to_string(count));
  return array;
}

ReceiverMesh receiverFromJson(const Json& value, const std::string& path, const Scene& scene) {
  expectObject(value, path);
  ReceiverMesh receiver;

  const std::string objectId = expectString(requireKey(value, "object", path), keyPath(path, "object"));
  const auto object = scene.findObject(objectId);
  if (!object) fail(keyPath(path, "object"), "unknown object '" + objectId + "'");
  receiver.face.object = scene.handleOf(*object);
  receiver.face.face = expectIndex(requireKey(value, "face", path), keyPath(path, "face"),
                                   scene.objects()[*object].faces.size());

  const std::string normalPath = keyPath(path, "normal");
  receiver.normal = expectVec3(requireKey(value, "normal", path), normalPath);
  if (!(std::abs(glm::length(receiver.normal) - 1) <= kRelativePlanarity))
    fail(normalPath, "normal is not of unit length (length " + shortNumber(glm::length(receiver.normal)) + ")");

  const std::string positionsPath = keyPath(path, "positions");
  const Json& positions = expectArray(requireKey(value, "positions", path), positionsPath);
  for (size_t i = 0; i < positions.size(); ++i)
    receiver.positions.push_back(expectVec3(positions[i], indexPath(positionsPath, i)));
  const size_t count = receiver.positions.size();

  const Json& irradiance = perVertexArray(value, "irradiance", path, count);
  for (size_t i = 0; i < count; ++i) {
    const std::string itemPath = indexPath(keyPath(path, "irradiance"), i);
    const Vec3 e = expectVec3(irradiance[i], itemPath);
    if (e.x < 0 || e.y < 0 || e.z < 0) fail(itemPath, "irradiance is negative");
    receiver.irradiance.push_back(e);
  }

  const Json& classes = perVertexArray(value, "class", path, count);
  for (size_t i = 0; i < count; ++i)
    receiver.classes.push_back(lightClassFromJson(classes[i], indexPath(keyPath(path, "class"), i)));

  const std::string trianglesPath = keyPath(path, "triangles");
  const Json& triangles = expectArray(requireKey(value, "triangles", path), trianglesPath);
  for (size_t t = 0; t < triangles.size(); ++t) {
    const std::string trianglePath = indexPath(trianglesPath, t);
    const Json& triangle = expectArray(triangles[t], trianglePath);
    if (triangle.size() != 3)
      fail(trianglePath, "a triangle needs 3 indices, has " + std::to_string(triangle.size()));
    std::array<uint32_t, 3> indices{};
    for (size_t k = 0; k < 3; ++k) indices[k] = expectIndex(triangle[k], indexPath(trianglePath, k), count);
    if (indices[0] == indices[1] || indices[1] == indices[2] || indices[0] == indices[2])
      fail(trianglePath, "triangle repeats a vertex");
    receiver.triangles.push_back(indices);
  }
  return receiver;
}

// The receiver's object; throws std::out_of_range if the object has no such face.
const Object& receiverObject(const Scene& scene, const ReceiverMesh& r) {
  const Object& object = scene.object(r.face.object);
  if (r.face.face >= object.faces.size())
    throw std::out_of_range("mesh receiver names face " + std::to_string(r.face.face) + " of object '" +
                            object.id + "', which has " + std::to_string(object.faces.size()));
  return object;
}

Json receiverToJson(const Scene& scene, const ReceiverMesh& r) {
  const Object& object = receiverObject(scene, r);
  Json positions = Json::array(), irradiance = Json::array(), classes = Json::array(),
       triangles = Json::array();
  for (const Vec3& p : r.positions) positions.push_back(toJson(p));
  for (const Vec3& e : r.irradiance) irradiance.push_back(toJson(e));
  for (LightClass c : r.classes) classes.push_back(toString(c));
  for (const auto& t : r.triangles) triangles.push_back(Json::array({t[0], t[1], t[2]}));
  return Json{{"object", object.id},
              {"face", r.face.face},
              {"normal", toJson(r.normal)},
              {"positions", std::move(positions)},
              {"irradiance", std::move(irradiance)},
              {"class", std::move(classes)},
              {"triangles", std::move(triangles)}};
}

}  // namespace

Json meshToJson(const Scene& scene, const Mesh& mesh, const std::string& sceneName) {
  Json receivers = Json::array();
  for (const ReceiverMesh& r : mesh.receivers) receivers.push_back(receiverToJson(scene, r));
  return Json{{"format", kMeshFormat}, {"version", kMeshVersion}, {"scene", sceneName}, {"receivers", std::move(receivers)}};
}

namespace {

std::string compactText(const Json& value) { return value.dump(-1, ' ', false, Json::error_handler_t::replace); }

// `[item,item,…]`, each item written by `write`.
template <typename Items, typename Write>
void writeArray(std::ostream& out, const Items& items, Write write) {
  out << '[';
  bool first = true;
  for (const auto& item : items) {
    if (!first) out << ',';
    first = false;
    write(item);
  }
  out << ']';
}

// An object's members in the order a JSON object dumps them (sorted by key): `own` written by
// their functions, then `extra`'s members merged in, replacing an own member of the same name.
using MemberWriters = std::map<std::string, std::function<void()>>;
void writeObject(std::ostream& out, MemberWriters own, const Json& extra) {
  if (extra.is_object())
    for (auto member = extra.begin(); member != extra.end(); ++member)
      own[member.key()] = [&out, value = &member.value()] { out << compactText(*value); };
  out << '{';
  bool first = true;
  for (const auto& [key, write] : own) {
    if (!first) out << ',';
    first = false;
    out << compactText(key) << ':';
    write();
  }
  out << '}';
}

// receiverToJson's text without the document, each number through the JSON library's own
// formatting, with `extra`'s members; `valuesOnly`: object, face and irradiance alone.
void writeReceiver(std::ostream& out, const Scene& scene, const ReceiverMesh& r, const Json& extra,
                   bool valuesOnly) {
  const Object& object = receiverObject(scene, r);
  const auto vec3 = [&](const Vec3& v) { out << compactText(toJson(v)); };
  MemberWriters own;
  own["face"] = [&] { out << r.face.face; };
  own["irradiance"] = [&] { writeArray(out, r.irradiance, vec3); };
  own["object"] = [&] { out << compactText(object.id); };
  if (valuesOnly) return writeObject(out, std::move(own), extra);
  own["class"] = [&] {
    writeArray(out, r.classes, [&](LightClass c) { out << '"' << toString(c) << '"'; });
  };
  own["normal"] = [&] { out << compactText(toJson(r.normal)); };
  own["positions"] = [&] { writeArray(out, r.positions, vec3); };
  own["triangles"] = [&] {
    writeArray(out, r.triangles, [&](const std::array<uint32_t, 3>& t) { out << '[' << t[0] << ',' << t[1] << ',' << t[2] << ']'; });
  };
  writeObject(out, std::move(own), extra);
}

}  // namespace

void writeMeshJson(std::ostream& out, const Scene& scene, const Mesh& mesh, const std::string& sceneName) {
  writeMeshJson(out, scene, mesh, sceneName, MeshJsonExtras{});
}

void writeMeshJson(std::ostream& out, const Scene& scene, const Mesh& mesh, const std::string& sceneName,
                   const MeshJsonExtras& extras) {
  // Members sorted as a JSON object dumps them, so the text is meshToJson's (with the extras).
  MemberWriters own;
  own["format"] = [&] { out << compactText(kMeshFormat); };
  own["receivers"] = [&] {
    out << '[';
    for (size_t k = 0; k < mesh.receivers.size(); ++k) {
      if (k) out << ',';
      writeReceiver(out, scene, mesh.receivers[k], extras.receiver ? extras.receiver(k) : Json(),
                    extras.valuesOnly && extras.valuesOnly(k));
    }
    out << ']';
  };
  own["scene"] = [&] { out << compactText(sceneName); };
  own["version"] = [&] { out << kMeshVersion; };
  writeObject(out, std::move(own), extras.root);
  out << '\n';
}

Mesh meshFromJson(const Json& root, const Scene& scene) {
  expectHeader(root, kMeshFormat, kMeshVersion);
  expectString(requireKey(root, "scene", ""), "scene");
  const Json& receivers = expectArray(requireKey(root, "receivers", ""), "receivers");
  Mesh mesh;
  for (size_t i = 0; i < receivers.size(); ++i)
    mesh.receivers.push_back(receiverFromJson(receivers[i], indexPath("receivers", i), scene));
  // What the mesh meets (a file written before these keys states nothing: fans, 0).
  if (const Json* tolerance = optionalKey(root, "tolerance")) {
    mesh.tolerance = expectNumber(*tolerance, "tolerance");
    if (!(mesh.tolerance >= 0)) fail("tolerance", "must be at least 0 (0: not refined)");
  }
  if (const Json* capped = optionalKey(root, "capped_cells"))
    mesh.cappedCells = expectIndex(*capped, "capped_cells", std::numeric_limits<uint32_t>::max());
  return mesh;
}

nlohmann::json meshFileRoot(const Mesh& mesh) {
  return Json{{"tolerance", mesh.tolerance}, {"capped_cells", mesh.cappedCells}};
}

void saveMeshFile(const Scene& scene, const Mesh& mesh, const std::string& sceneName, const std::string& path) {
  // A receiver naming no face of the scene throws before the file is opened, as it did when the
  // whole document was made first.
  for (const ReceiverMesh& r : mesh.receivers) (void)receiverObject(scene, r);
  MeshJsonExtras extras;
  extras.root = meshFileRoot(mesh);
  writeTextFileWith(path, [&](std::ostream& out) { writeMeshJson(out, scene, mesh, sceneName, extras); });
}

Mesh loadMeshFile(const std::string& path, const Scene& scene) {
  return meshFromJson(parseJsonText(readTextFile(path, kMaxJsonFileBytes), kMaxJsonFileBytes, kMaxJsonDepth), scene);
}

}  // namespace penumbra::protocol
