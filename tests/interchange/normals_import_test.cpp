// A file's shading normals become the imported objects' corner normals: OBJ `vn` on a sphere
// (each corner gets its radial direction back, through welding), the per-face normals of a
// cube (creases stay sharp), a face without `vn` (shaded flat), and glTF NORMAL under a
// non-uniform node scale (mapped by the inverse transpose).
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "gltf_model_writer.h"
#include "interchange/obj_import.h"
#include "interchange/scene_import.h"
#include "interchange_fixtures.h"

namespace penumbra::interchange {
namespace {

using testing::scratchDir;
using testing::writeFile;

constexpr double kPi = 3.14159265358979323846;
const std::string kLamp = "mtllib n.mtl\no lamp\nusemtl lamp\nv -0.5 3 -0.5\nv 0.5 3 -0.5\nv 0.5 3 0.5\nv -0.5 3 0.5\nf 1 2 3 4\n";
const std::string kNormalsMtl = "newmtl grey\nKd 0.5 0.5 0.5\nnewmtl lamp\nKe 5 5 5\n";

// A UV sphere of radius r at `centre`: positions, and triangles counter-clockwise from outside.
void uvSphere(const Vec3& centre, double r, int rings, int segments, std::vector<Vec3>& points,
              std::vector<std::array<int, 3>>& triangles) {
  const int first = int(points.size());
  points.push_back(centre + Vec3(0, r, 0));
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double t = kPi * i / rings, p = 2 * kPi * j / segments;
      points.push_back(centre + r * Vec3(std::sin(t) * std::cos(p), std::cos(t), std::sin(t) * std::sin(p)));
    }
  points.push_back(centre - Vec3(0, r, 0));
  const int bottom = int(points.size()) - 1;
  auto at = [&](int i, int j) { return first + 1 + (i - 1) * segments + (j % segments); };
  for (int j = 0; j < segments; ++j) triangles.push_back({first, at(1, j + 1), at(1, j)});
  for (int i = 1; i + 1 < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  for (int j = 0; j < segments; ++j) triangles.push_back({bottom, at(rings - 1, j), at(rings - 1, j + 1)});
}

const Object& namedObject(const Scene& scene, const std::string& id) {
  const auto index = scene.findObject(id);
  EXPECT_TRUE(index) << id;
  return scene.objects()[*index];
}

TEST(NormalsImport, ObjVertexNormalsOfASphereComeBackAtEveryCorner) {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  const Vec3 centre(0.2, 1.1, -0.3);
  uvSphere(centre, 0.4, 8, 12, points, triangles);
  std::ostringstream obj;
  obj.precision(17);
  obj << kLamp << "o ball\nusemtl grey\n";
  for (const Vec3& p : points) obj << "v " << p.x << " " << p.y << " " << p.z << "\n";
  for (const Vec3& p : points) {
    const Vec3 n = glm::normalize(p - centre);
    obj << "vn " << n.x << " " << n.y << " " << n.z << "\n";
  }
  const int base = 5;  // after the lamp's four vertices
  for (const auto& t : triangles)
    obj << "f " << t[0] + base << "//" << t[0] + 1 << " " << t[1] + base << "//" << t[1] + 1 << " " << t[2] + base
        << "//" << t[2] + 1 << "\n";
  const auto dir = scratchDir();
  writeFile(dir / "n.obj", obj.str());
  writeFile(dir / "n.mtl", kNormalsMtl);
  const ImportResult result = importObjFile((dir / "n.obj").string(), {});
  const Object& ball = namedObject(result.scene, "ball");
  ASSERT_EQ(ball.normals.size(), ball.faces.size());
  size_t corners = 0;
  for (size_t f = 0; f < ball.faces.size(); ++f)
    for (size_t k = 0; k < ball.faces[f].size(); ++k) {
      const Vec3 radial = glm::normalize(ball.vertices[size_t(ball.faces[f][k])] - centre);
      EXPECT_NEAR(glm::length(ball.normals[f][k] - radial), 0, 1e-9) << "face " << f;
      ++corners;
    }
  EXPECT_EQ(corners, 3 * ball.faces.size());
  EXPECT_EQ(result.report.repaired("corners_shaded_flat_without_a_file_normal"), 0u);
  // The scene takes them: every face of the ball has its corner normals.
  for (const Face& face : result.scene.faces())
    if (result.scene.object(face.id.object).id == "ball") EXPECT_EQ(face.cornerNormals.size(), 3u);
}

TEST(NormalsImport, ACubeWithFaceNormalsStaysSharpAndAFaceWithoutVnIsFlat) {
  // Eight shared vertices; each face names its own normal; the top face has no vn.
  const std::string cube =
      "o box\nusemtl grey\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"
      "vn 0 0 -1\nvn 0 0 1\nvn -1 0 0\nvn 1 0 0\nvn 0 -1 0\nvn 0 1 0\n"
      "f 5//1 8//1 7//1 6//1\n"  // the z = 0 face, facing -z
      "f 9//2 10//2 11//2 12//2\n"
      "f 5//3 9//3 12//3 8//3\n"
      "f 6//4 7//4 11//4 10//4\n"
      "f 5//5 6//5 10//5 9//5\n"
      "f 8 12 11 7\n";
  const auto dir = scratchDir();
  writeFile(dir / "n.obj", kLamp + cube);
  writeFile(dir / "n.mtl", kNormalsMtl);
  const ImportResult result = importObjFile((dir / "n.obj").string(), {});
  const Object& box = namedObject(result.scene, "box");
  ASSERT_EQ(box.normals.size(), box.faces.size());
  for (const Face& face : result.scene.faces()) {
    if (result.scene.object(face.id.object).id != "box") continue;
    // Every corner's normal is its own face's: the neighbours' lie 90° away (a crease).
    ASSERT_EQ(face.cornerNormals.size(), face.polygon.size());
    for (const Vec3& n : face.cornerNormals) EXPECT_NEAR(glm::dot(n, face.plane.normal), 1.0, 1e-12);
  }
  EXPECT_EQ(result.report.repaired("corners_shaded_flat_without_a_file_normal"), 4u) << result.report.summary();
}

TEST(NormalsImport, GltfNormalsFollowANonUniformNodeScale) {
  std::vector<Vec3> points;
  std::vector<std::array<int, 3>> triangles;
  uvSphere(Vec3(0.0), 0.3, 8, 12, points, triangles);
  ModelWriter w;
  const int grey = w.material("grey", {0.5, 0.5, 0.5}, {0, 0, 0}, 1);
  const int lamp = w.material("lamp", {1, 1, 1}, {1, 1, 1}, 5);
  w.quad("lamp", {{{-0.5, 0, -0.5}, {0.5, 0, -0.5}, {0.5, 0, 0.5}, {-0.5, 0, 0.5}}}, lamp, {0, 3, 0});
  std::vector<float> positions, normals;
  std::vector<uint16_t> indices;
  for (const Vec3& p : points) {
    const Vec3 n = glm::normalize(p);
    positions.insert(positions.end(), {float(p.x), float(p.y), float(p.z)});
    normals.insert(normals.end(), {float(n.x), float(n.y), float(n.z)});
  }
  for (const auto& t : triangles)
    for (int i : t) indices.push_back(uint16_t(i));
  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.material = grey;
  primitive.attributes["POSITION"] = w.accessor(positions.data(), positions.size() * 4, points.size(),
                                                TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  primitive.attributes["NORMAL"] = w.accessor(normals.data(), normals.size() * 4, points.size(),
                                              TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  primitive.indices = w.accessor(indices.data(), indices.size() * 2, indices.size(),
                                 TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR);
  w.node("egg", primitive, Vec3(2, 1, 1), Vec3(0, 1, 0));
  const ImportResult result = importSceneBytes(w.write(true), "egg.glb", {}, {});
  const Object& egg = namedObject(result.scene, "egg");
  ASSERT_EQ(egg.normals.size(), egg.faces.size());
  // On the ellipsoid x²/4 + y² + z² = r² (centred at (0, 1, 0)) the normal is (x/4, y, z):
  // the file's normals are unit radial in float, so within float precision of it.
  for (size_t f = 0; f < egg.faces.size(); ++f)
    for (size_t k = 0; k < egg.faces[f].size(); ++k) {
      const Vec3 d = egg.vertices[size_t(egg.faces[f][k])] - Vec3(0, 1, 0);
      const Vec3 expected = glm::normalize(Vec3(d.x / 4, d.y, d.z));
      EXPECT_NEAR(glm::length(egg.normals[f][k] - expected), 0, 1e-6) << "face " << f;
    }
}

}  // namespace
}  // namespace penumbra::interchange
