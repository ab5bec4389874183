// A mesh backprojected as one chain (shadow_chain.h) equals its faces backprojected one by
// one and the exact reference, at 1e-9 of the unoccluded light, on seeded non-convex,
// open and inconsistently oriented meshes seen from random points (issue 35).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/illum/backprojection.h"
#include "core/illum/mesh_box_chain.h"
#include "core/reference/exact_irradiance.h"
#include "core/scene/mesh_topology.h"
#include "tests/core/illum/random_meshes.h"

namespace penumbra {
namespace {

Object floorQuad() {
  Object o;
  o.id = "floor";
  o.vertices = {{-4, 0, -4}, {-4, 0, 4}, {4, 0, 4}, {4, 0, -4}};
  o.faces = {{0, 1, 2, 3}};
  return o;
}

double visibleOneByOne(const Scene& scene, uint32_t handle, const Vec3& p, const Vec3& n) {
  Backprojection view(scene, 0, p, n);
  for (const Face& face : scene.facesOfObject(handle)) view.occlude(face);
  return view.visibleFactor();
}

TEST(MeshChain, EqualsFaceByFaceAndReferenceOnSeededMeshes) {
  size_t penumbra = 0, umbra = 0, checked = 0;
  for (uint64_t seed = 1; seed <= 6; ++seed)
    for (test::NamedMesh& c : test::seededMeshes(seed)) {
      const Scene scene({test::ceilingLight(0.5 + 0.1 * double(seed))}, {}, {floorQuad(), c.mesh});
      const uint32_t handle = scene.handleOf(1);
      ASSERT_NE(scene.meshTopology(handle), nullptr) << c.name;
      const ExactReference reference(scene);
      std::mt19937_64 rng(seed * 7919);
      std::uniform_real_distribution<double> u(-1.2, 1.2);
      std::uniform_real_distribution<double> height(0.2, 2.4);
      for (int i = 0; i < 90; ++i) {
        // Floor points, and points on a wall plane beside the mesh at its height: there part
        // of the mesh lies above p (nearer p's height than the chain allows), projected
        // face by face beside the chain of the rest.
        const bool wall = i >= 60;
        const Vec3 p = wall ? Vec3(-0.5, height(rng), u(rng)) : Vec3(u(rng), 0, u(rng));
        const Vec3 n = wall ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        Backprojection view(scene, 0, p, n);
        view.occludeObject(handle);
        const double chain = view.visibleFactor(), full = view.unoccludedFactor();
        const double faces = visibleOneByOne(scene, handle, p, n);
        const LightVisibility truth = reference.visibility(p, n, 0);
        EXPECT_NEAR(chain, faces, 1e-9 * full) << c.name << " seed " << seed << " p " << p.x << "," << p.z;
        EXPECT_NEAR(chain, truth.visibleFactor, 1e-9 * full) << c.name << " seed " << seed;
        // Classes agree unless either is penumbra (a point on a boundary may take either side's).
        if (view.lightClass() != LightClass::Penumbra && truth.lightClass != LightClass::Penumbra)
          EXPECT_EQ(view.lightClass(), truth.lightClass) << c.name << " seed " << seed;
        penumbra += view.lightClass() == LightClass::Penumbra;
        umbra += view.lightClass() == LightClass::Umbra;
        ++checked;
      }
    }
  // The sample must exercise the interesting cases, not only lit points.
  EXPECT_GT(penumbra, checked / 4);
  EXPECT_GT(umbra, 10u);
}

// Points on the mesh's own faces (a face's own normal, off its corners and edges): nearby
// faces rise in front of p's plane and reach past p's height, so most points mix the chain
// with faces the chain cannot hold. Chain and faces one by one and the reference agree.
TEST(MeshChain, PointsOnTheMeshesOwnFacesEqualFaceByFaceAndReference) {
  size_t penumbra = 0, checked = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed)
    for (test::NamedMesh& c : test::seededMeshes(seed)) {
      const Scene scene({test::ceilingLight(0.5 + 0.1 * double(seed))}, {}, {floorQuad(), c.mesh});
      const uint32_t handle = scene.handleOf(1);
      const std::span<const Face> faces = scene.facesOfObject(handle);
      const ExactReference reference(scene);
      std::mt19937_64 rng(seed * 104729);
      std::uniform_real_distribution<double> u(0.05, 1.0);
      for (int i = 0; i < 120; ++i) {
        const Face& face = faces[rng() % faces.size()];
        // A point inside the face: a convex combination of three of its corners, off the edges.
        double a = u(rng), b = u(rng), w = u(rng);
        const double sum = a + b + w;
        a /= sum, b /= sum, w /= sum;
        const size_t k = face.polygon.size();
        const Vec3 p = a * face.polygon[0] + b * face.polygon[k / 2] + w * face.polygon[k - 1];
        const Vec3 n = face.plane.normal;
        Backprojection view(scene, 0, p, n);
        view.occludeObject(handle);
        const double chain = view.visibleFactor(), full = view.unoccludedFactor();
        const double oneByOne = visibleOneByOne(scene, handle, p, n);
        const LightVisibility truth = reference.visibility(p, n, 0);
        EXPECT_NEAR(chain, oneByOne, 1e-9 * full) << c.name << " seed " << seed << " point " << i;
        EXPECT_NEAR(chain, truth.visibleFactor, 1e-9 * full) << c.name << " seed " << seed << " point " << i;
        penumbra += view.lightClass() == LightClass::Penumbra;
        ++checked;
      }
    }
  EXPECT_GT(penumbra, checked / 8);
}

// The seeded meshes moved down onto the floor (lowest corner on it) or into it (2 cm): floor
// points take a box's summed chain with the faces touching the floor decided per point
// (mesh_box_chain.h, `special`), or their own pass where such a face blocks on its own
// (beside the contact). Both equal the faces one by one and the reference.
TEST(MeshChain, RestingMeshesEqualFaceByFaceAndReference) {
  size_t checked = 0, boxWithSpecial = 0, specialAlone = 0, penumbra = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed)
    for (test::NamedMesh& c : test::seededMeshes(seed)) {
      const double sink = seed % 2 ? 0.0 : 0.02;
      double lowest = INFINITY;
      for (const Vec3& v : c.mesh.vertices) lowest = std::min(lowest, v.y);
      for (Vec3& v : c.mesh.vertices) v.y -= lowest + sink;
      // Under a ceiling light, or lit from a window-like light on a wall: there a floor box
      // spans distances to the light's plane, and the faces at those distances are usable
      // from some of its points and not from others.
      const bool window = seed > 2;
      Light light = test::ceilingLight(0.5 + 0.1 * double(seed));
      if (window) light.polygon = {{2, 0.4, -0.5}, {2, 0.4, 0.5}, {2, 1.4, 0.5}, {2, 1.4, -0.5}};
      const Scene scene({light}, {}, {floorQuad(), c.mesh});
      const uint32_t handle = scene.handleOf(1);
      const MeshTopology& mesh = *scene.meshTopology(handle);
      const ExactReference reference(scene);
      std::mt19937_64 rng(seed * 6151);
      std::uniform_real_distribution<double> near(-0.7, 0.7), far(-1.6, 1.6), low(0.0, 0.3), behind(-1.6, -0.2);
      for (int i = 0; i < 150; ++i) {
        // Floor points near the mesh and farther, points on a wall beside it low down, where a
        // box spans heights that leave the faces between them usable from some of its points
        // and not from others, and points of a tilted plane through the mesh's foot (above the
        // floor), whose box is a slab of a cube, not flat.
        const bool wall = i >= 80 && i < 120, tilted = i >= 120;
        const Vec3 tilt = glm::normalize(Vec3(0.15, 1, 0.05));
        const double x = -0.3 - 0.35 * (near(rng) + 0.7) / 1.4, z = near(rng);  // y > 0.01 on the plane
        const Vec3 p = tilted   ? Vec3(x, -(tilt.x * x + tilt.z * z) / tilt.y, z)
                       : wall   ? Vec3(-0.62, low(rng), near(rng))
                       : window ? Vec3(i % 2 ? near(rng) : behind(rng), 0, near(rng))
                       : i % 2  ? Vec3(near(rng), 0, near(rng))
                                : Vec3(far(rng), 0, far(rng));
        const Vec3 n = tilted ? tilt : wall ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
        Backprojection view(scene, 0, p, n);
        view.occludeObject(handle);
        const double chain = view.visibleFactor(), full = view.unoccludedFactor();
        const double faces = visibleOneByOne(scene, handle, p, n);
        EXPECT_NEAR(chain, faces, 1e-9 * full) << c.name << " seed " << seed << " p " << p.x << "," << p.z;
        EXPECT_NEAR(chain, reference.visibility(p, n, 0).visibleFactor, 1e-9 * full) << c.name << " seed " << seed;
        penumbra += view.lightClass() == LightClass::Penumbra;
        ++checked;
        const MeshBoxChain* box = meshBoxChain(mesh, p, n, light.polygon, light.plane(), scene.tolerance());
        if (!box || !box->usable || box->special.empty()) continue;
        ++boxWithSpecial;
        // Whether one of the box's special faces not usable from p shades p on its own (p then
        // takes its own pass).
        for (const uint32_t k : box->special) {
          Backprojection alone(scene, 0, p, n);
          const Face& face = scene.facesOfObject(handle)[mesh.clusterFaces[k]];
          bool usable = true;
          for (const Vec3& v : face.polygon) usable = usable && glm::dot(n, v - p) > 0 && (!wall || v.y > p.y);
          if (!usable && alone.occlude(face) && alone.visibleFactor() < alone.unoccludedFactor() * (1 - 1e-12)) {
            ++specialAlone;
            break;
          }
        }
      }
    }
  // The sample must reach both ways through the box and the shadows' penumbrae.
  EXPECT_GT(boxWithSpecial, checked / 4);
  EXPECT_GT(specialAlone, 5u);
  EXPECT_LT(specialAlone, boxWithSpecial / 2);
  EXPECT_GT(penumbra, checked / 5);
}

// A plate standing near floor points, lit from a window-like light on a wall: the plate's
// distance to the light's plane lies within a floor box's, so its faces are special there,
// yet usable from points farther from the light, which it shades (in their chain, or by the
// point's own pass: either way it must shade them).
TEST(MeshChain, AFaceSpecialToItsBoxStillShadesThePoints) {
  Object plates;
  plates.id = "plates";
  // Plate A near the points (facing the light, +x; 2 × 2 cells), plate B far off (8 × 8
  // cells: it sets the box size, and keeps plate A's faces a small share of the mesh's).
  const auto addPlate = [&](const Vec3& corner, const Vec3& up, const Vec3& across, int cells) {
    const int first = int(plates.vertices.size());
    for (int j = 0; j <= cells; ++j)
      for (int k = 0; k <= cells; ++k) plates.vertices.push_back(corner + (double(j) / cells) * up + (double(k) / cells) * across);
    for (int j = 0; j < cells; ++j)
      for (int k = 0; k < cells; ++k) {
        const int a = first + (cells + 1) * j + k, b = a + 1, c = a + cells + 2, d = a + cells + 1;
        plates.faces.push_back({a, c, b});
        plates.faces.push_back({a, d, c});
      }
  };
  addPlate({-0.47, 0.01, -0.2}, {0, 0.29, 0}, {0, 0, 0.4}, 2);
  addPlate({0.5, 1.0, 0.4}, {0, 0.2, 0}, {0, 0, 0.2}, 8);
  Light light = test::ceilingLight(0.5);
  light.polygon = {{2, 0.4, -0.5}, {2, 0.4, 0.5}, {2, 1.4, 0.5}, {2, 1.4, -0.5}};
  const Scene scene({light}, {}, {floorQuad(), plates});
  const uint32_t handle = scene.handleOf(1);
  ASSERT_NE(scene.meshTopology(handle), nullptr);
  const MeshTopology& mesh = *scene.meshTopology(handle);
  const ExactReference reference(scene);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> x(-0.56, -0.48), z(-0.15, 0.15);
  size_t shadedWhileSpecial = 0;
  for (int i = 0; i < 200; ++i) {
    const Vec3 p(x(rng), 0, z(rng)), n(0, 1, 0);
    Backprojection view(scene, 0, p, n);
    view.occludeObject(handle);
    const double full = view.unoccludedFactor();
    EXPECT_NEAR(view.visibleFactor(), visibleOneByOne(scene, handle, p, n), 1e-9 * full) << i;
    EXPECT_NEAR(view.visibleFactor(), reference.visibility(p, n, 0).visibleFactor, 1e-9 * full) << i;
    const MeshBoxChain* box = meshBoxChain(mesh, p, n, light.polygon, light.plane(), scene.tolerance());
    if (box && box->usable && std::any_of(box->special.begin(), box->special.end(), [&](uint32_t k) {
          return mesh.clusterFaces[k] < 8 && view.visibleFactor() < full * (1 - 1e-6);
        }))
      ++shadedWhileSpecial;
  }
  // Points where plate A is special in a usable box and shades them.
  EXPECT_GT(shadedWhileSpecial, 20u);
}

// A mesh and a convex face of another object over one point: the union of both.
TEST(MeshChain, CombinesWithConvexShadows) {
  Object board;
  board.id = "board";
  board.vertices = {{-0.2, 2.2, -0.6}, {-0.2, 2.2, 0.3}, {0.5, 2.2, 0.3}, {0.5, 2.2, -0.6}};
  board.faces = {{0, 1, 2, 3}};
  const Scene scene({test::ceilingLight(0.7)}, {}, {floorQuad(), test::torus("m", {0.1, 1.2, 0.0}, 0.4, 0.12, 20, 8, 0.7), board});
  const uint32_t mesh = scene.handleOf(1);
  const Face& boardFace = scene.facesOfObject(scene.handleOf(2))[0];
  const ExactReference reference(scene);
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int i = 0; i < 80; ++i) {
    const Vec3 p(u(rng), 0, u(rng)), n(0, 1, 0);
    Backprojection view(scene, 0, p, n);
    view.occludeObject(mesh);
    view.occlude(boardFace);
    EXPECT_NEAR(view.visibleFactor(), reference.visibility(p, n, 0).visibleFactor, 1e-9 * view.unoccludedFactor()) << i;
  }
}

TEST(MeshTopology, RegularEdgesAndCornersOfClosedAndOpenMeshes) {
  const Scene scene({test::ceilingLight(0.5)}, {},
                    {floorQuad(), test::torus("t", {0, 1, 0}, 0.4, 0.1, 12, 6, 0.3), test::bowl("b", {2, 1, 2}, 0.4, 8, 0.0, 1)});
  const MeshTopology& closed = *scene.meshTopology(scene.handleOf(1));
  EXPECT_EQ(std::count(closed.regularEdge.begin(), closed.regularEdge.end(), 1), long(closed.regularEdge.size()));
  const MeshTopology& open = *scene.meshTopology(scene.handleOf(2));
  const long irregular = std::count(open.regularEdge.begin(), open.regularEdge.end(), 0);
  EXPECT_EQ(irregular, 16);  // the rim: 16 slices
  EXPECT_EQ(scene.meshTopology(scene.handleOf(0)), nullptr);  // one face: cast face by face
}

}  // namespace
}  // namespace penumbra

namespace penumbra {
namespace {

// Near-degenerate meshes through the chain (the family of the 1-µm-off cube and its
// coincident copy, for meshes): two coincident copies, rings a micron apart (nearly
// coplanar neighbours), one corner moved a micron.
TEST(MeshChain, NearDegenerateMeshesEqualFaceByFace) {
  size_t checked = 0;
  for (uint64_t seed = 1; seed <= 4; ++seed) {
    Object flat = test::bumpySphere("flat", {0.05, 1.2, 0.0}, 0.45, 10, 1e-6, seed);
    Object moved = test::torus("moved", {0.0, 1.3, 0.05}, 0.45, 0.15, 20, 8, 0.4);
    moved.vertices[seed * 7].x += 1e-6;
    Object copy = moved;
    copy.id = "copy";
    const Scene scene({test::ceilingLight(0.6)}, {}, {floorQuad(), flat, moved, copy});
    const ExactReference reference(scene);
    std::mt19937_64 rng(seed * 104729);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < 60; ++i) {
      const Vec3 p(u(rng), 0, u(rng)), n(0, 1, 0);
      for (uint32_t object : {1u, 2u}) {  // the near-flat sphere alone; the torus with its copy
        Backprojection view(scene, 0, p, n);
        view.occludeObject(scene.handleOf(object));
        if (object == 2) view.occludeObject(scene.handleOf(3));
        Backprojection faces(scene, 0, p, n);
        for (uint32_t o = object; o <= (object == 2 ? 3u : 1u); ++o)
          for (const Face& face : scene.facesOfObject(scene.handleOf(o))) faces.occlude(face);
        EXPECT_NEAR(view.visibleFactor(), faces.visibleFactor(), 1e-9 * view.unoccludedFactor())
            << "seed " << seed << " object " << object << " p " << p.x << "," << p.z;
        ++checked;
      }
    }
  }
  EXPECT_EQ(checked, 480u);
}

}  // namespace
}  // namespace penumbra
