// Scene JSON v1: exact round trips (in memory, through text, through files),
// mirrored transforms, the Euler convention, and the SCENE_FORMAT.md example.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <unistd.h>

#include <glm/gtc/matrix_transform.hpp>
#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include "protocol/json_text.h"
#include "protocol/scene_json.h"
#include "scene_fixtures.h"

namespace penumbra::protocol {
namespace {

using nlohmann::json;
using testing::baseSceneJson;
using testing::cubeFaces;
using testing::cubeVertices;
using testing::expectSameScene;

Scene roundTrip(const Scene& scene) { return sceneFromJson(sceneToJson(scene)); }
Scene roundTripText(const Scene& scene) {
  return sceneFromJson(parseJsonText(sceneToJson(scene).dump(), kMaxJsonFileBytes, kMaxJsonDepth));
}

std::filesystem::path tempPath(const std::string& name) {
  return std::filesystem::temp_directory_path() /
         ("penumbra_protocol_" + std::to_string(::getpid()) + "_" + name);
}

TEST(SceneJson, BaseSceneRoundTripsExactly) {
  const Scene scene = sceneFromJson(baseSceneJson());
  expectSameScene(scene, roundTrip(scene));
  expectSameScene(scene, roundTripText(scene));
}

TEST(SceneJson, WriterFollowsTheFormat) {
  const Scene scene = sceneFromJson(baseSceneJson());
  const json out = sceneToJson(scene);
  EXPECT_EQ(out["format"], "penumbra.scene");
  EXPECT_EQ(out["version"], 1);
  EXPECT_EQ(out["lights"][0]["id"], "lamp");
  EXPECT_EQ(out["materials"]["red"]["albedo"], json::array({0.7, 0.1, 0.1}));
  EXPECT_EQ(out["objects"][0]["static"], true);
  EXPECT_FALSE(out["objects"][1].contains("static"));  // default false is omitted
  EXPECT_EQ(out["objects"][1]["transform"]["rotate_deg"], json::array({0.0, 30.0, 0.0}));
  EXPECT_FALSE(out["objects"][0].contains("transform"));  // identity is omitted
  EXPECT_FALSE(out["objects"][2].contains("material"));
  EXPECT_EQ(out["objects"][1]["faces"], cubeFaces());
  EXPECT_EQ(out["camera"]["projection"], "perspective");
  EXPECT_EQ(out["camera"]["fov_y_deg"], 45.0);
  // The writer's output is itself a valid scene with the same content.
  EXPECT_EQ(sceneToJson(sceneFromJson(out)), out);
}

TEST(SceneJson, SceneWithoutCameraOrMaterials) {
  json j = baseSceneJson();
  j.erase("camera");
  j.erase("materials");
  for (auto& object : j["objects"]) object.erase("material");
  const Scene scene = sceneFromJson(j);
  EXPECT_FALSE(scene.camera());
  EXPECT_TRUE(scene.materials().empty());
  expectSameScene(scene, roundTrip(scene));
  EXPECT_FALSE(sceneToJson(scene).contains("camera"));
}

TEST(SceneJson, FullPrecisionNumbersSurviveText) {
  // Values whose shortest decimal form needs all 17 significant digits.
  json j = baseSceneJson();
  j["objects"][1]["transform"]["translate"] = json::array({0.1 + 0.2, 1.0 / 3.0, -std::nextafter(1.0, 2.0)});
  j["objects"][1]["transform"]["rotate_deg"] = json::array({M_PI, std::sqrt(2.0), 1e-300});
  j["lights"][0]["radiance"] = json::array({1.0 / 7.0, 123456789.123456789, 5e-324});
  const Scene scene = sceneFromJson(j);
  expectSameScene(scene, roundTripText(scene));
  EXPECT_EQ(scene.objects()[1].transform.translate.x, 0.1 + 0.2);
}

// Outward-facing check: every world face's front normal points away from the
// object's world centre (the cube is convex and contains its centre).
void expectOutwardFaces(const Scene& scene, size_t objectIndex) {
  const Object& object = scene.objects()[objectIndex];
  const Vec3 center = object.transform.apply(Vec3(0.0));
  for (const Face& face : scene.faces()) {
    if (face.id.object != objectIndex) continue;
    EXPECT_GT(glm::dot(face.plane.normal, centroid(face.polygon) - center), 0)
        << "face " << face.id.face << " of " << object.id << " faces inward";
  }
}

TEST(SceneJson, MirroredCubeKeepsOutwardNormals) {
  for (const json& scale : {json::array({-1, 1, 1}), json::array({1, -2, 0.5}), json::array({-1, -1, 1}),
                            json::array({-1, -1, -1}), json::array({1, 1, 1})}) {
    SCOPED_TRACE(scale.dump());
    json j = baseSceneJson();
    j["objects"][1]["transform"]["scale"] = scale;
    const Scene scene = sceneFromJson(j);
    expectOutwardFaces(scene, 1);
    expectOutwardFaces(scene, 2);
    // A mirror reverses the winding in world space; a proper transform keeps it.
    const Object& box = scene.objects()[1];
    const bool mirrors = scale[0].get<double>() * scale[1].get<double>() * scale[2].get<double>() < 0;
    for (const Face& face : scene.faces()) {
      if (face.id.object != 1) continue;
      Polygon3 mapped;
      for (int index : box.faces[face.id.face]) mapped.push_back(box.transform.apply(box.vertices[index]));
      if (mirrors) std::reverse(mapped.begin(), mapped.end());
      EXPECT_EQ(face.polygon, mapped);
    }
    expectSameScene(scene, roundTripText(scene));
  }
}

// R = Rx(x)·Ry(y)·Rz(z) computed with glm::rotate, independent of core/scene.
Mat3 threeJsXyz(const Vec3& degrees) {
  const glm::dmat4 m = glm::rotate(glm::dmat4(1.0), glm::radians(degrees.x), glm::dvec3(1, 0, 0)) *
                       glm::rotate(glm::dmat4(1.0), glm::radians(degrees.y), glm::dvec3(0, 1, 0)) *
                       glm::rotate(glm::dmat4(1.0), glm::radians(degrees.z), glm::dvec3(0, 0, 1));
  return Mat3(m);
}

double maxDifference(const Mat3& a, const Mat3& b) {
  double worst = 0;
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) worst = std::max(worst, std::abs(a[c][r] - b[c][r]));
  return worst;
}

TEST(SceneJson, EulerAnglesFollowThreeJsXyz) {
  json j = baseSceneJson();
  j["objects"][1]["transform"] = {{"rotate_deg", {90, 0, 0}}};
  Scene scene = sceneFromJson(j);
  const double eps = scene.tolerance().length();
  // Rx(90°) turns +y into +z (right-handed).
  const Vec3 y = scene.objects()[1].transform.apply(Vec3(0, 1, 0));
  EXPECT_LT(glm::length(y - Vec3(0, 0, 1)), eps) << y.x << " " << y.y << " " << y.z;

  const Vec3 angles(30, -50, 70);
  j["objects"][1]["transform"] = {{"translate", {0.25, 0.5, -1}}, {"rotate_deg", {angles.x, angles.y, angles.z}},
                                  {"scale", {2, 0.5, -1}}};
  scene = sceneFromJson(j);
  const Transform& t = scene.objects()[1].transform;
  const Mat3 expected = threeJsXyz(angles);
  EXPECT_LT(maxDifference(t.rotation(), expected), eps);
  // The other order is really different, so the check above can fail.
  const Mat3 zyx = Mat3(glm::rotate(glm::dmat4(1.0), glm::radians(angles.z), glm::dvec3(0, 0, 1)) *
                        glm::rotate(glm::dmat4(1.0), glm::radians(angles.y), glm::dvec3(0, 1, 0)) *
                        glm::rotate(glm::dmat4(1.0), glm::radians(angles.x), glm::dvec3(1, 0, 0)));
  EXPECT_GT(maxDifference(zyx, expected), 0.1);
  // v' = T + R·(S·v), on the world vertices of the derived faces.
  const Vec3 v = scene.objects()[1].vertices[6];
  const Vec3 world = Vec3(0.25, 0.5, -1) + expected * (Vec3(2, 0.5, -1) * v);
  EXPECT_LT(glm::length(t.apply(v) - world), eps);
}

TEST(SceneJson, ParsesTheFormatDocumentExample) {
  // SCENE_FORMAT.md's example, with its [...] placeholders replaced by a cube.
  std::string text = R"({
  "format": "penumbra.scene",
  "version": 1,
  "lights": [
    { "id": "lamp",
      "polygon": [[-0.5, 2.99, -0.5], [-0.5, 2.99, 0.5], [0.5, 2.99, 0.5], [0.5, 2.99, -0.5]],
      "radiance": [10.0, 10.0, 10.0] }
  ],
  "materials": {
    "white": { "albedo": [0.8, 0.8, 0.8] },
    "red":   { "albedo": [0.7, 0.1, 0.1] }
  },
  "objects": [
    { "id": "floor",
      "vertices": [[-3, 0, -3], [-3, 0, 3], [3, 0, 3], [3, 0, -3]],
      "faces": [[0, 1, 2, 3]],
      "material": "white",
      "static": true },
    { "id": "box1",
      "vertices": VERTICES,
      "faces": FACES,
      "material": "red",
      "transform": { "translate": [0, 0.5, 0], "rotate_deg": [0, 30, 0], "scale": [1, 1, 1] } }
  ],
  "camera": { "position": [0, 1.5, 6], "target": [0, 1, 0], "up": [0, 1, 0],
              "projection": "perspective", "fov_y_deg": 45, "near": 0.1, "far": 100 }
})";
  text.replace(text.find("VERTICES"), 8, cubeVertices().dump());
  text.replace(text.find("FACES"), 5, cubeFaces().dump());
  const Scene scene = sceneFromJson(parseJsonText(text, kMaxJsonFileBytes, kMaxJsonDepth));

  ASSERT_EQ(scene.lights().size(), 1u);
  EXPECT_EQ(scene.lights()[0].id, "lamp");
  EXPECT_EQ(scene.lights()[0].radiance, Vec3(10.0));
  ASSERT_EQ(scene.objects().size(), 2u);
  EXPECT_EQ(scene.objects()[0].id, "floor");
  EXPECT_TRUE(scene.objects()[0].isStatic);
  EXPECT_FALSE(scene.objects()[1].isStatic);
  EXPECT_EQ(scene.objects()[1].material, "red");
  EXPECT_EQ(scene.objects()[1].transform.rotateDeg, Vec3(0, 30, 0));
  EXPECT_EQ(scene.faces().size(), 7u);
  const auto red = scene.findMaterial("red");
  ASSERT_TRUE(red);
  EXPECT_EQ(scene.materials()[*red].albedo, Vec3(0.7, 0.1, 0.1));
  ASSERT_TRUE(scene.camera());
  EXPECT_EQ(scene.camera()->position, Vec3(0, 1.5, 6));
  EXPECT_EQ(scene.camera()->far, 100);
  // The floor faces up.
  EXPECT_GT(scene.faces()[0].plane.normal.y, 0);
  expectOutwardFaces(scene, 1);
}

TEST(SceneJson, FilesRoundTrip) {
  const Scene scene = sceneFromJson(baseSceneJson());
  const auto path = tempPath("scene.json");
  saveSceneFile(scene, path.string());
  expectSameScene(scene, loadSceneFile(path.string()));
  std::filesystem::remove(path);
}

TEST(SceneJson, FileErrors) {
  EXPECT_THROW((void)loadSceneFile(tempPath("does_not_exist.json").string()), std::runtime_error);
  EXPECT_THROW((void)loadSceneFile(tempPath("does_not_exist.json").string()), std::exception);

  const auto path = tempPath("broken.json");
  writeTextFile(path.string(), "{\"format\": \"penumbra.scene\", \"version\": 1,");
  try {
    (void)loadSceneFile(path.string());
    FAIL();
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), kJsonTextPath);
    EXPECT_NE(e.problem().find("at byte"), std::string::npos) << e.what();
  }

  // A sparse file one byte over the limit is refused before it is read.
  std::filesystem::resize_file(path, kMaxJsonFileBytes + 1);
  try {
    (void)loadSceneFile(path.string());
    FAIL();
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.path(), kJsonTextPath);
    EXPECT_NE(e.problem().find("over the limit"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// Random valid scenes: parallelepipeds (random linear images of the cube) with
// random transforms, random rectangular lights, random materials and camera.
// Full-mantissa doubles everywhere, so any precision loss shows.
Scene randomScene(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(-1.0, 1.0), positive(0.1, 2.0), zeroOne(0.0, 1.0);
  auto randomVec = [&] { return Vec3(unit(rng), unit(rng), unit(rng)); };

  std::vector<Light> lights;
  const int lightCount = 1 + int(rng() % 3);
  for (int i = 0; i < lightCount; ++i) {
    const Vec3 c = randomVec() + Vec3(0, 4, 0);
    const double w = positive(rng), d = positive(rng);
    lights.push_back(Light{"light" + std::to_string(i),
                           {c + Vec3(-w, 0, -d), c + Vec3(w, 0, -d), c + Vec3(w, 0, d), c + Vec3(-w, 0, d)},
                           Vec3(positive(rng), positive(rng), positive(rng)) * 10.0});
  }
  std::vector<Material> materials;
  const int materialCount = int(rng() % 4);
  for (int i = 0; i < materialCount; ++i) {
    Material m{"m" + std::to_string(i), Vec3(zeroOne(rng), zeroOne(rng), zeroOne(rng))};
    m.type = MaterialType(rng() % 4);
    if (m.type != MaterialType::Diffuse) {  // the microfacet keys, each type with its own
      m.roughness = rng() % 2 ? Vec2(0.01 + zeroOne(rng)) : Vec2(0.01 + zeroOne(rng), 0.01 + zeroOne(rng));
      m.ndf = rng() % 2 ? bsdf::Ndf::GGX : bsdf::Ndf::Beckmann;
      m.singleScattering = rng() % 2;
      if (m.type == MaterialType::Conductor) {
        m.eta = Vec3(positive(rng), positive(rng), positive(rng));
        m.k = Vec3(zeroOne(rng), zeroOne(rng), zeroOne(rng)) * 5.0;
      }
      if (m.type == MaterialType::Dielectric) m.ior = 1.01 + 2 * zeroOne(rng);
    }
    materials.push_back(m);
  }

  std::vector<Object> objects;
  const int objectCount = int(rng() % 5);
  for (int i = 0; i < objectCount; ++i) {
    Object object;
    object.id = "object " + std::to_string(i);
    // A well-conditioned linear map keeps the faces planar and convex.
    const Mat3 shape = Mat3(1.0) + 0.3 * Mat3(randomVec(), randomVec(), randomVec());
    const Vec3 offset = randomVec();
    for (const auto& v : cubeVertices()) {
      const Vec3 p(v[0].get<double>(), v[1].get<double>(), v[2].get<double>());
      object.vertices.push_back(shape * p + offset);
    }
    object.faces = cubeFaces().get<std::vector<std::vector<int>>>();
    if (!materials.empty() && rng() % 2) object.material = materials[rng() % materials.size()].id;
    object.isStatic = rng() % 2;
    if (rng() % 3) {
      auto sign = [&] { return rng() % 2 ? 1.0 : -1.0; };
      object.transform = Transform{randomVec() * 3.0, randomVec() * 180.0,
                                   Vec3(sign() * positive(rng), sign() * positive(rng), sign() * positive(rng))};
    }
    objects.push_back(std::move(object));
  }
  std::optional<Camera> camera;
  if (rng() % 2) {
    camera = Camera{};
    camera->position = randomVec() + Vec3(0, 0, 8);
    camera->target = randomVec();
    camera->projection = rng() % 2 ? Camera::Projection::Perspective : Camera::Projection::Orthographic;
    camera->fovYDeg = 20 + 100 * zeroOne(rng);
    camera->height = positive(rng);
    camera->near = 0.01 * positive(rng);
    camera->far = 50 + zeroOne(rng);
  }
  return Scene(std::move(lights), std::move(materials), std::move(objects), camera);
}

TEST(SceneJson, RandomScenesRoundTripExactly) {
  std::mt19937_64 rng(20240611);
  for (int trial = 0; trial < 200; ++trial) {
    SCOPED_TRACE(trial);
    const Scene scene = randomScene(rng);
    // The protocol must accept every scene core can hold that obeys the format.
    expectSameScene(scene, roundTripText(scene));
    if (::testing::Test::HasFailure()) break;
  }
}

// Random damage to a valid scene: the reader either accepts it or refuses it
// with a ValidationError; nothing else escapes, and it never crashes.
RC_GTEST_PROP(SceneJsonProperty, RandomDamageIsRefusedCleanly, ()) {
  json scene = baseSceneJson();
  // Collect every value's JSON pointer, then replace a few of them.
  std::vector<json::json_pointer> pointers;
  const json flat = scene.flatten();
  for (const auto& [key, value] : flat.items()) pointers.emplace_back(key);
  const std::vector<json> replacements = {
      json(nullptr), json(-1), json(0), json(1e308), json(0.5), json("x"), json::array(), json::object(),
      json::array({1, 2, 3}), json(true), json(std::numeric_limits<double>::infinity()), json(4294967296.0)};
  const int damage = *rc::gen::inRange(1, 4);
  for (int i = 0; i < damage; ++i) {
    const auto& pointer = pointers[*rc::gen::inRange<size_t>(0, pointers.size())];
    const bool removeKey = *rc::gen::arbitrary<bool>();
    const auto& replacement = replacements[*rc::gen::inRange<size_t>(0, replacements.size())];
    try {
      const auto parent = pointer.parent_pointer();
      if (removeKey && !parent.empty() && scene.contains(parent) && scene[parent].is_object())
        scene[parent].erase(pointer.back());
      else if (scene.contains(pointer))
        scene[pointer] = replacement;
    } catch (const json::exception&) {
      // An earlier change made this pointer meaningless (e.g. its parent is now a number).
    }
  }
  try {
    const Scene parsed = sceneFromJson(scene);
    // Accepted damage must still describe a scene that round-trips.
    const Scene again = roundTripText(parsed);
    RC_ASSERT(again.faces().size() == parsed.faces().size());
    RC_TAG("accepted");
  } catch (const ValidationError& e) {
    RC_TAG("refused");
    RC_ASSERT(std::string(e.what()).size() > 0);
  }
}

}  // namespace
}  // namespace penumbra::protocol

namespace penumbra::protocol {
namespace {

// Corner normals (smooth shading) survive writing and reading bit for bit; an object without
// them writes none.
TEST(SceneJson, CornerNormalsRoundTripExactly) {
  nlohmann::json base = testing::baseSceneJson();
  nlohmann::json lists = nlohmann::json::array();
  for (int f = 0; f < 6; ++f) {
    nlohmann::json corners = nlohmann::json::array();
    for (int k = 0; k < 4; ++k) corners.push_back({0.1 * k + 0.01 * f, 1.0 / 3.0, -0.25});
    lists.push_back(corners);
  }
  base["objects"][2]["normals"] = lists;
  const Scene scene = sceneFromJson(base);
  const nlohmann::json written = sceneToJson(scene);
  EXPECT_EQ(written["objects"][2]["normals"], lists);
  EXPECT_FALSE(written["objects"][1].contains("normals"));
  const Scene again = sceneFromJson(written);
  EXPECT_EQ(again.objects()[2].normals, scene.objects()[2].normals);
}

}  // namespace
}  // namespace penumbra::protocol
