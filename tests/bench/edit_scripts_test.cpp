// The edit-script generators: deterministic per seed, their scripts parse and
// apply to the scene they came from, moved shares close to what was asked, and
// the shipped bench/edits scripts are what the generator writes today.
#include "bench/lib/edit_scripts.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "bench/lib/cubes_scene.h"
#include "protocol/edits_json.h"
#include "protocol/scene_json.h"

namespace penumbra {
namespace {

std::string text(const EditScript& script) { return protocol::writeEditScript(script.frames); }

size_t faceCount(const Scene& scene) { return scene.faces().size(); }

// Plays the frames on the scene model with the engine's rules (edits in order);
// fails the test at the first refusal.
void expectApplies(Scene scene, const EditScript& script) {
  for (size_t f = 0; f < script.frames.size(); ++f)
    for (const Edit& edit : script.frames[f].edits) {
      if (edit.op == Edit::Op::Add) {
        ASSERT_FALSE(scene.findObject(edit.object.id)) << script.name << " frame " << f;
        ASSERT_NO_THROW(scene.addObject(edit.object)) << script.name << " frame " << f;
        continue;
      }
      const auto index = scene.findObject(edit.id);
      ASSERT_TRUE(index) << script.name << " frame " << f << ": " << edit.id;
      if (edit.op == Edit::Op::Move)
        ASSERT_NO_THROW(scene.setTransform(scene.handleOf(*index), edit.transform));
      else
        scene.removeObject(scene.handleOf(*index));
    }
}

TEST(EditScripts, DeterministicPerSeed) {
  CubesSceneOptions options;
  options.cubes = 40;
  options.seed = 3;
  const Scene scene = makeCubesScene(options);
  for (uint64_t seed : {1u, 2u}) {
    EXPECT_EQ(text(dragScript(scene, 20, seed)), text(dragScript(scene, 20, seed)));
    EXPECT_EQ(text(moveShareScript(scene, 0.1, 5, seed)),
              text(moveShareScript(scene, 0.1, 5, seed)));
    EXPECT_EQ(text(removeAddScript(scene, 3, seed)), text(removeAddScript(scene, 3, seed)));
  }
  EXPECT_NE(text(moveShareScript(scene, 0.1, 5, 1)), text(moveShareScript(scene, 0.1, 5, 2)));
  EXPECT_EQ(text(buildUpScript(scene, 10)), text(buildUpScript(scene, 10)));
}

TEST(EditScripts, ScriptsParseAndApply) {
  for (int cubes : {15, 60}) {
    CubesSceneOptions options;
    options.cubes = cubes;
    const Scene scene = makeCubesScene(options);
    for (const EditScript& script : standardEditScripts(scene, 7)) {
      SCOPED_TRACE(script.name);
      ASSERT_FALSE(script.frames.empty());
      const std::vector<Frame> read = protocol::readEditScript(text(script), &scene.materials());
      ASSERT_EQ(read.size(), script.frames.size());
      for (size_t i = 0; i < read.size(); ++i)
        EXPECT_EQ(protocol::frameToJson(read[i]), protocol::frameToJson(script.frames[i]));
      expectApplies(scene, script);
    }
  }
}

TEST(EditScripts, SharesOfFacesRoughlyAsAsked) {
  CubesSceneOptions options;
  options.cubes = 300;
  const Scene scene = makeCubesScene(options);
  for (double share : {0.01, 0.05, 0.10, 0.30}) {
    const EditScript script = moveShareScript(scene, share, 3, 5);
    EXPECT_NEAR(script.faceShare, share, 0.1 * share + 6.5 / double(faceCount(scene))) << share;
    // Every frame moves the same objects, whose faces are the share.
    size_t faces = 0;
    for (const Edit& edit : script.frames[0].edits)
      faces += scene.objects()[*scene.findObject(edit.id)].faces.size();
    EXPECT_EQ(faces, script.editedFaces);
    for (const Frame& frame : script.frames)
      EXPECT_EQ(frame.edits.size(), script.frames[0].edits.size());
  }
}

TEST(EditScripts, DragIsSmallStepsOfOneFreeCubeInsideTheRoom) {
  CubesSceneOptions options;
  options.cubes = 150;
  const Scene scene = makeCubesScene(options);
  const EditScript drag = dragScript(scene, 100, 1);
  ASSERT_EQ(drag.frames.size(), 100u);
  const std::string id = drag.frames[0].edits.at(0).id;
  EXPECT_EQ(id.rfind("cube_", 0), 0u);
  Vec3 previous = scene.objects()[*scene.findObject(id)].transform.translate;
  double travelled = 0;
  for (const Frame& frame : drag.frames) {
    ASSERT_EQ(frame.edits.size(), 1u);
    EXPECT_EQ(frame.edits[0].id, id);
    const Vec3 t = frame.edits[0].transform.translate;
    EXPECT_LE(glm::length(t - previous), 0.0801);
    travelled += glm::length(t - previous);
    EXPECT_LT(std::abs(t.x), scene.bounds().max.x);
    EXPECT_LT(std::abs(t.z), scene.bounds().max.z);
    previous = t;
  }
  EXPECT_GT(travelled, 1.0);  // across the room, not on the spot
}

TEST(EditScripts, BuildUpStartsFromTheEmptyRoom) {
  CubesSceneOptions options;
  options.cubes = 12;
  const Scene scene = makeCubesScene(options);
  const EditScript script = buildUpScript(scene, 0);
  const size_t movable = movableObjects(scene).size();
  ASSERT_EQ(script.frames.size(), movable + 1);
  EXPECT_EQ(script.frames[0].edits.size(), movable);
  for (size_t i = 1; i < script.frames.size(); ++i) {
    ASSERT_EQ(script.frames[i].edits.size(), 1u);
    EXPECT_EQ(script.frames[i].edits[0].op, Edit::Op::Add);
  }
  EXPECT_EQ(buildUpScript(scene, 4).frames.size(), 5u);
}

TEST(EditScripts, ShippedScriptsAreTheGeneratorsOutput) {
  const std::string root = PENUMBRA_SOURCE_DIR;
  const Scene scene = protocol::loadSceneFile(root + "/scenes/cubes15.scene.json");
  for (const EditScript& script : standardEditScripts(scene, 1)) {
    const std::string path = root + "/bench/edits/cubes15." + script.name + ".edits.jsonl";
    std::ifstream in(path);
    ASSERT_TRUE(in) << path
                    << " (regenerate: penumbra-bench edits --write-scripts bench/edits --scene "
                       "scenes/cubes15.scene.json)";
    std::stringstream shipped;
    shipped << in.rdbuf();
    EXPECT_EQ(shipped.str(), text(script)) << path;
  }
}

}  // namespace
}  // namespace penumbra
