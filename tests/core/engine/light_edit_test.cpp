// Engine::apply with set_light edits: a moved or resized light gives exactly what a
// fresh build of the edited scene gives (a counted full rebuild), a new radiance alone
// rescales every value without geometry work and equals a fresh build too, and bad
// light edits are refused with the key path, changing nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "core/engine/engine.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "scenegen/cubes_scene.h"
#include "tests/core/engine/incremental_compare.h"
#include "tests/core/engine/refused_frame.h"

namespace penumbra {
namespace {

using testing::centroid;
using testing::moveEditBy;
using testing::scaledMoved;
using testing::expectRefusedUnchanged;
using testing::meshText;
using testing::sceneText;


// A fresh scene made of the engine's lights, materials and objects: its bounds and
// tolerance are computed anew, as a loaded file's are.
Scene freshScene(const Scene& scene) {
  return Scene(scene.lights(), scene.materials(), scene.objects(), scene.camera());
}

Edit setLight(const std::string& id, std::optional<Polygon3> polygon,
              std::optional<Vec3> radiance) {
  Edit edit;
  edit.op = Edit::Op::SetLight;
  edit.id = id;
  edit.polygon = std::move(polygon);
  edit.radiance = radiance;
  return edit;
}

TEST(LightEdit, MovedAndResizedLightEqualsAFreshBuild) {
  Engine engine(makeCubesScene(CubesSceneOptions{6, 3}));
  engine.apply(Frame{{moveEditBy(engine, "cube_1", Vec3(0.05, 0, 0))}});  // not a fresh build
  const Light light = engine.scene().lights()[0];
  const Polygon3 grown = scaledMoved(light.polygon, 1.6, Vec3(0.4, -0.2, 0.3));
  const Bounds before = engine.scene().bounds();

  const FrameResult result = engine.apply(Frame{{setLight("light", grown, std::nullopt)}});
  EXPECT_EQ(result.version, 2u);
  EXPECT_TRUE(result.fullRebuild);
  EXPECT_EQ(result.treeRebuilds, engine.receivers().size());
  EXPECT_EQ(engine.scene().lights()[0].polygon, grown);
  EXPECT_EQ(engine.scene().lights()[0].radiance, light.radiance);
  EXPECT_NO_THROW(engine.validate());

  // The light stayed inside the room: a fresh scene has the same bounds, so a fresh
  // build is the same engine, mesh for mesh, bit for bit.
  const Scene fresh = freshScene(engine.scene());
  ASSERT_EQ(fresh.bounds().min, before.min);
  ASSERT_EQ(fresh.bounds().max, before.max);
  Engine rebuilt(fresh);
  EXPECT_EQ(meshText(engine), meshText(rebuilt));
  const testing::EngineDiff diff =
      testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 200, 7);
  EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;

  // A bigger light at the same place widens the penumbrae: more vertices in penumbra.
  Engine small(makeCubesScene(CubesSceneOptions{6, 3}));
  Engine big(makeCubesScene(CubesSceneOptions{6, 3}));
  big.apply(Frame{{setLight("light", scaledMoved(light.polygon, 1.8, Vec3(0.0)), std::nullopt)}});
  EXPECT_GT(big.stats().penumbraVertices, small.stats().penumbraVertices);
}

TEST(LightEdit, RadianceAloneRescalesExactly) {
  Engine engine(makeCubesScene(CubesSceneOptions{5, 4}));
  (void)engine.mesh();  // the display memo filled: a new radiance must relight none of its cells
  const std::vector<Engine::Receiver> before = engine.receivers();
  std::vector<std::vector<VertexIrradiance>> valuesBefore(before.size());
  for (size_t r = 0; r < before.size(); ++r)
    for (VertexId v : before[r].tree.vertices()) valuesBefore[r].push_back(engine.value(before[r], v));
  const Vec3 radiance = engine.scene().lights()[0].radiance;
  const FrameResult result = engine.apply(Frame{{setLight("light", std::nullopt, 2.0 * radiance)}});
  EXPECT_FALSE(result.fullRebuild);
  EXPECT_TRUE(result.radianceChanged);
  EXPECT_EQ(result.treeRebuilds, 0u);
  EXPECT_EQ(result.changedReceivers.size(), engine.receivers().size());
  EXPECT_GT(result.verticesChanged, 0u);
  EXPECT_EQ(result.verticesCreated, 0u);
  // One light: every value doubles (a power of two: exactly), the trees are untouched.
  ASSERT_EQ(engine.receivers().size(), before.size());
  for (size_t r = 0; r < before.size(); ++r) {
    ASSERT_EQ(engine.receivers()[r].tree.vertexCount(), before[r].tree.vertexCount());
    const std::vector<VertexId> vertices = before[r].tree.vertices();
    for (size_t i = 0; i < vertices.size(); ++i) {
      const VertexIrradiance now = engine.value(engine.receivers()[r], vertices[i]);
      EXPECT_EQ(now.irradiance, 2.0 * valuesBefore[r][i].irradiance);
      EXPECT_EQ(now.lightClass, valuesBefore[r][i].lightClass);
    }
  }
  Engine rebuilt(freshScene(engine.scene()));
  EXPECT_EQ(meshText(engine), meshText(rebuilt));
  // The chunks were summed again with the new radiance; no cell was lit again (issue 35).
  EXPECT_EQ(engine.lastMeshCounters().cellsLit, 0u);
  EXPECT_GT(engine.lastMeshCounters().chunksMeshed, 0u);
  EXPECT_EQ(engine.lastMeshCounters().chunksKept, 0u);
  EXPECT_NO_THROW(engine.validate());
}

// Two lights, one made brighter and the other coloured: values only, each light's share
// rescaled, the display mesh equal to a rebuild's byte for byte and no cell lit again.
TEST(LightEdit, RadianceOfOneOfTwoLightsRelightsNoCell) {
  Engine engine(makeCubesScene(mixedCubesOptions(17)));
  ASSERT_EQ(engine.scene().lights().size(), 2u);
  (void)engine.mesh();
  engine.apply(Frame{{setLight("light_2", std::nullopt, Vec3(0.5, 3.0, 7.25))}});
  Engine rebuilt(freshScene(engine.scene()));
  EXPECT_EQ(meshText(engine), meshText(rebuilt));
  EXPECT_EQ(engine.lastMeshCounters().cellsLit, 0u);
  engine.apply(Frame{{setLight("light", std::nullopt, Vec3(0.0))}});  // switched off
  Engine rebuilt2(freshScene(engine.scene()));
  EXPECT_EQ(meshText(engine), meshText(rebuilt2));
  EXPECT_EQ(engine.lastMeshCounters().cellsLit, 0u);
}

// Light and object edits in one frame, then again after incremental frames: the result
// equals a rebuild of the scene the frame leaves (sceneAfter).
TEST(LightEdit, MixedFramesEqualARebuild) {
  Engine engine(makeCubesScene(mixedCubesOptions(17)));  // two tilted lights
  ASSERT_EQ(engine.scene().lights().size(), 2u);
  const Light second = engine.scene().lights()[1];
  const std::vector<Frame> frames = {
      Frame{{moveEditBy(engine, "cube_0", Vec3(0.04, 0, 0)),
             setLight("light_2", std::nullopt, Vec3(1, 2, 3))}},
      Frame{{setLight("light_2", scaledMoved(second.polygon, 0.7, Vec3(-0.2, 0, 0.1)), Vec3(5.0)),
             moveEditBy(engine, "cube_0", Vec3(-0.04, 0, 0.02))}},
      Frame{{setLight("light", std::nullopt, Vec3(0.0))}},  // switched off
  };
  for (size_t f = 0; f < frames.size(); ++f) {
    SCOPED_TRACE("frame " + std::to_string(f));
    const std::string expected = protocol::sceneToJson(engine.sceneAfter(frames[f])).dump();
    engine.apply(frames[f]);
    EXPECT_EQ(sceneText(engine), expected);
    EXPECT_NO_THROW(engine.validate());
    const Engine rebuilt(engine.scene());
    const testing::EngineDiff diff =
        testing::compareEngines(engine, rebuilt, testing::peakIrradiance(rebuilt), 100, f);
    EXPECT_EQ(diff.errors(), 0u) << diff.firstProblem;
  }
}

TEST(LightEdit, BadLightEditsChangeNothing) {
  Engine engine(makeCubesScene(CubesSceneOptions{4, 2}));
  engine.apply(Frame{{moveEditBy(engine, "cube_0", Vec3(0.05, 0, 0))}});
  const Polygon3 square = engine.scene().lights()[0].polygon;
  const Edit move = moveEditBy(engine, "cube_0", Vec3(0.02, 0, 0));

  expectRefusedUnchanged(engine, Frame{{move, setLight("lamp", std::nullopt, Vec3(1.0))}}, 1, "id");
  expectRefusedUnchanged(engine, Frame{{setLight("cube_0", std::nullopt, Vec3(1.0))}}, 0,
                         "id");  // an object
  expectRefusedUnchanged(engine, Frame{{setLight("light", std::nullopt, std::nullopt)}}, 0, "");
  expectRefusedUnchanged(engine, Frame{{move, setLight("light", std::nullopt, Vec3(1, -1, 1))}}, 1,
                         "radiance");
  expectRefusedUnchanged(engine, Frame{{setLight("light", std::nullopt, Vec3(1, NAN, 1))}}, 0,
                         "radiance");
  expectRefusedUnchanged(engine, Frame{{setLight("light", std::nullopt, Vec3(INFINITY))}}, 0,
                         "radiance");

  Polygon3 bent = square;
  bent[0].y += 0.3;
  expectRefusedUnchanged(engine, Frame{{setLight("light", bent, std::nullopt)}}, 0, "polygon");
  Polygon3 concave = square;
  concave[1] = centroid(square) +
               0.3 * (square[3] - centroid(square));  // a dent towards the opposite corner
  expectRefusedUnchanged(engine, Frame{{setLight("light", concave, std::nullopt)}}, 0, "polygon");
  expectRefusedUnchanged(engine,
                         Frame{{setLight("light", Polygon3{square[0], square[1]}, std::nullopt)}},
                         0, "polygon");
  // Thinner than the scene's minimum face width.
  const Vec3 c = centroid(square);
  const Polygon3 sliver{c, c + Vec3(1, 0, 0), c + Vec3(1, 0, 1e-9), c + Vec3(0, 0, 1e-9)};
  expectRefusedUnchanged(engine, Frame{{setLight("light", sliver, std::nullopt)}}, 0, "polygon");
  // Out of the edit volume (the room grown by 5% of its diagonal), on a later edit.
  expectRefusedUnchanged(
      engine,
      Frame{{move, setLight("light", scaledMoved(square, 1, Vec3(0, 50, 0)), std::nullopt)}}, 1,
      "polygon[0]");
  // A later edit of the frame refers to the light as the earlier one left it.
  const Polygon3 moved = scaledMoved(square, 1, Vec3(0.1, 0, 0));
  engine.apply(
      Frame{{setLight("light", moved, std::nullopt), setLight("light", std::nullopt, Vec3(3.0))}});
  EXPECT_EQ(engine.scene().lights()[0].polygon, moved);
  EXPECT_EQ(engine.scene().lights()[0].radiance, Vec3(3.0));
}

// A loaded light thinner than the minimum face width (the file's checks do not apply that
// rule to lights) still takes a new radiance; a new polygon that thin is refused.
TEST(LightEdit, SceneSetLightChecksOnlyANewPolygon) {
  Scene scene = makeCubesScene(CubesSceneOptions{2, 1});
  const Vec3 c = centroid(scene.lights()[0].polygon);
  const Polygon3 thin{c, c + Vec3(1, 0, 0), c + Vec3(1, 0, 1e-9), c + Vec3(0, 0, 1e-9)};
  std::vector<Light> lights = scene.lights();
  lights[0].polygon = thin;
  Scene loaded(lights, scene.materials(), scene.objects());
  EXPECT_NO_THROW(loaded.setLight(0, thin, Vec3(2.0)));
  EXPECT_EQ(loaded.lights()[0].radiance, Vec3(2.0));
  EXPECT_THROW(scene.setLight(0, thin, Vec3(2.0)), std::invalid_argument);
  EXPECT_NE(scene.lights()[0].polygon, thin);
}

}  // namespace
}  // namespace penumbra
