// Volume objects in scene files and the NRRD reader (Teem): a generated field read back voxel
// for voxel (raw and gzip, three types), spacings and space directions, the key paths of every
// refusal, and hostile files (truncated, wrong sizes, unknown type / encoding, gzip garbage,
// detached data, huge headers) that each give a clear error.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "core/engine/engine.h"
#include "protocol/json_text.h"
#include "protocol/nrrd_volume.h"
#include "protocol/scene_json.h"
#include "protocol/validation_error.h"
#include "protocol/volume_json.h"
#include "scenegen/volume_fields.h"

namespace penumbra::protocol {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// A fresh folder per test under the system's temporary directory.
class VolumeSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("penumbra_volume_" +
            std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  void writeText(const std::string& name, const std::string& text) const {
    std::ofstream(path(name), std::ios::binary) << text;
  }
  // A scene with a floor and one volume object whose keys are `volume` (merged over defaults).
  std::string writeScene(const Json& volume) const {
    Json object = {{"id", "blob"}, {"type", "volume"}, {"file", "blob.nrrd"}, {"isovalue", 127.5}};
    for (const auto& [key, value] : volume.items()) {
      if (value.is_null())
        object.erase(key);
      else
        object[key] = value;
    }
    const Json scene = {
        {"format", "penumbra.scene"},
        {"version", 1},
        {"lights",
         {{{"id", "lamp"},
           {"polygon", {{-0.5, 3, -0.5}, {0.5, 3, -0.5}, {0.5, 3, 0.5}, {-0.5, 3, 0.5}}},
           {"radiance", {10, 10, 10}}}}},
        {"materials", {{"white", {{"albedo", {0.8, 0.8, 0.8}}}}}},
        {"objects",
         {{{"id", "floor"},
           {"vertices", {{-3, 0, -3}, {-3, 0, 3}, {3, 0, 3}, {3, 0, -3}}},
           {"faces", {{0, 1, 2, 3}}}},
          object}}};
    writeText("scene.json", scene.dump());
    return path("scene.json");
  }
  // The ValidationError loading the scene gives (fails the test if it loads).
  ValidationError refusal(const Json& volume) const {
    const std::string scene = writeScene(volume);
    try {
      loadSceneFile(scene);
    } catch (const ValidationError& error) {
      return error;
    }
    ADD_FAILURE() << "the scene loaded";
    return ValidationError("", "");
  }
  std::string nrrdHeader(const std::string& type, const std::string& sizes,
                         const std::string& encoding, const std::string& extra = "") const {
    return "NRRD0004\ntype: " + type + "\ndimension: 3\nsizes: " + sizes +
           "\nencoding: " + encoding + "\nendian: little\n" + extra + "\n";
  }

  fs::path dir_;
};

volume::DenseGrid<float> sphereField(int n) {
  VolumeFieldSpec spec;
  spec.field = VolumeField::Sphere;
  spec.size = glm::ivec3(n, n + 1, n + 2);  // three different sides: axis order matters
  return makeVolumeField(spec);
}

template <class T>
void expectSameVoxels(const volume::DenseGrid<T>& grid, const volume::ScalarVolume& read) {
  ASSERT_EQ(read.size(), grid.size);
  for (int z = 0; z < grid.size.z; ++z)
    for (int y = 0; y < grid.size.y; ++y)
      for (int x = 0; x < grid.size.x; ++x)
        ASSERT_EQ(read.voxel({x, y, z}), double(grid.at({x, y, z}))) << x << " " << y << " " << z;
  const auto [lo, hi] = std::minmax_element(grid.values.begin(), grid.values.end());
  EXPECT_EQ(read.minValue(), double(*lo));
  EXPECT_EQ(read.maxValue(), double(*hi));
}

TEST_F(VolumeSceneTest, GeneratedFieldsReadBackInEveryTypeAndEncoding) {
  const auto field = sphereField(9);
  for (const bool gzip : {false, true}) {
    writeNrrdVolume(path("u8.nrrd"), quantise8(field), Vec3(0.5), gzip);
    writeNrrdVolume(path("u16.nrrd"), quantise16(field), Vec3(0.5), gzip);
    writeNrrdVolume(path("f32.nrrd"), field, Vec3(0.5), gzip);
    const auto u8 = readNrrdVolume(path("u8.nrrd"));
    const auto u16 = readNrrdVolume(path("u16.nrrd"));
    const auto f32 = readNrrdVolume(path("f32.nrrd"));
    EXPECT_EQ(u8->typeName(), "uchar");
    EXPECT_EQ(u16->typeName(), "ushort");
    EXPECT_EQ(f32->typeName(), "float");
    expectSameVoxels(quantise8(field), *u8);
    expectSameVoxels(quantise16(field), *u16);
    expectSameVoxels(field, *f32);
    EXPECT_EQ(f32->objectFromVoxel(), Mat3(0.5));
  }
}

TEST_F(VolumeSceneTest, VoxelOrderIsXFastest) {
  // One hot voxel at (3, 1, 2) in a 5×4×3 grid: a ray along z through x = 3, y = 1 meets the
  // 0.5 level set between z = 1 and z = 2, a ray through x = 1 meets nothing.
  volume::DenseGrid<uint8_t> grid(glm::ivec3(5, 4, 3));
  grid[glm::ivec3(3, 1, 2)] = 200;
  writeNrrdVolume(path("hot.nrrd"), grid, Vec3(1.0));
  const auto read = readNrrdVolume(path("hot.nrrd"));
  volume::VolumeRay ray;
  ray.origin = Vec3(3, 1, -1);
  ray.dir = Vec3(0, 0, 1);
  const auto hit = read->trace(ray, 100.0);
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 2.5, 1e-9);  // z = 1.5: halfway from 0 to 200 crosses 100
  ray.origin = Vec3(1, 1, -1);
  EXPECT_FALSE(read->trace(ray, 100.0));
}

TEST_F(VolumeSceneTest, SpaceDirectionsAndSpacingsSetTheVoxelMap) {
  const std::string data(4 * 4 * 4, '\0');
  writeText("sd.nrrd",
            "NRRD0005\ntype: uchar\ndimension: 3\nspace: right-anterior-superior\nsizes: 4 4 4\n"
            "space directions: (0,0.5,0) (2,0,0) (0,0,0.25)\nencoding: raw\n\n" +
                data);
  const Mat3 map = readNrrdVolume(path("sd.nrrd"))->objectFromVoxel();
  EXPECT_EQ(map[0], Vec3(0, 0.5, 0));  // column a = axis a's direction
  EXPECT_EQ(map[1], Vec3(2, 0, 0));
  EXPECT_EQ(map[2], Vec3(0, 0, 0.25));
  writeText("sp.nrrd", nrrdHeader("uchar", "4 4 4", "raw", "spacings: 0.1 0.2 0.3\n") + data);
  EXPECT_EQ(readNrrdVolume(path("sp.nrrd"))->objectFromVoxel(),
            Mat3(Vec3(0.1, 0, 0), Vec3(0, 0.2, 0), Vec3(0, 0, 0.3)));
  writeText("none.nrrd", nrrdHeader("uchar", "4 4 4", "raw") + data);
  EXPECT_EQ(readNrrdVolume(path("none.nrrd"))->objectFromVoxel(), Mat3(1.0));
}

TEST_F(VolumeSceneTest, SceneFileLoadsAVolumeRelativeToItsFolder) {
  fs::create_directories(dir_ / "data");
  writeNrrdVolume(path("data/blob.nrrd"), quantise8(sphereField(8)), Vec3(0.25));
  const Scene scene = loadSceneFile(writeScene({{"file", "data/blob.nrrd"},
                                                {"material", "white"},
                                                {"transform", {{"translate", {0, 1, 0}}}}}));
  ASSERT_EQ(scene.volumes().size(), 1u);
  ASSERT_EQ(scene.objects().size(), 1u);  // the floor; the volume is no DM object
  EXPECT_EQ(scene.faces().size(), 1u);
  const VolumeObject& volume = scene.volumes()[0];
  EXPECT_EQ(volume.id, "blob");
  EXPECT_EQ(volume.isovalue, 127.5);
  EXPECT_EQ(volume.material, "white");
  EXPECT_EQ(volume.file, fs::absolute(path("data/blob.nrrd")).lexically_normal().string());
  EXPECT_EQ(volume.worldFromVoxel() * glm::dvec4(4, 0, 0, 1), glm::dvec4(1, 1, 0, 1));
  // Written back with the resolved path, it reads back equal (the data is read again).
  const Json written = sceneToJson(scene);
  EXPECT_EQ(written["objects"][1]["type"], "volume");
  const VolumeFiles files;
  const Scene again = sceneFromJson(written, &files);
  EXPECT_EQ(sceneToJson(again), written);
}

TEST_F(VolumeSceneTest, VolumeEditsChangeTheVolumeOnlyAndBadOnesNothing) {
  writeNrrdVolume(path("blob.nrrd"), quantise8(sphereField(4)), Vec3(1.0));
  Engine engine(loadSceneFile(writeScene(Json::object())));
  const Mesh before = engine.mesh();
  // An object may not take a volume's id; a set_volume outside the data's values is refused.
  Edit add;
  add.op = Edit::Op::Add;
  add.object = engine.scene().objects()[0];
  add.object.id = "blob";
  Edit outside;
  outside.op = Edit::Op::SetVolume;
  outside.id = "blob";
  outside.isovalue = 1e6;
  for (const auto& [edit, where] : {std::pair{add, "object.id"}, std::pair{outside, "isovalue"}}) {
    try {
      engine.checkFrame(Frame{{edit}});
      ADD_FAILURE() << "a bad frame naming the volume passed";
    } catch (const EditError& error) {
      EXPECT_EQ(error.path(), where) << error.what();
    }
  }
  // A move and a set_volume change the volume, the version, and nothing of the DM.
  Edit move;
  move.op = Edit::Op::Move;
  move.id = "blob";
  move.transform.translate = Vec3(0.5, 0, 0);
  Edit iso = outside;
  iso.isovalue = 100;
  const FrameResult result = engine.apply(Frame{{move, iso}});
  EXPECT_EQ(result.version, 1u);
  EXPECT_TRUE(result.changedReceivers.empty());
  ASSERT_EQ(engine.scene().volumes().size(), 1u);
  EXPECT_EQ(engine.scene().volumes()[0].transform.translate, Vec3(0.5, 0, 0));
  EXPECT_EQ(engine.scene().volumes()[0].isovalue, 100);
  const Mesh after = engine.mesh();
  ASSERT_EQ(after.receivers.size(), before.receivers.size());
  for (size_t r = 0; r < after.receivers.size(); ++r)
    EXPECT_EQ(after.receivers[r].irradiance, before.receivers[r].irradiance);
}

TEST_F(VolumeSceneTest, OldScenesLoadUnchanged) {
  const Scene scene =
      loadSceneFile(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cornell.scene.json");
  EXPECT_TRUE(scene.volumes().empty());
  EXPECT_FALSE(scene.objects().empty());
}

TEST_F(VolumeSceneTest, KeysAreValidatedWithTheirPaths) {
  writeNrrdVolume(path("blob.nrrd"), quantise8(sphereField(4)), Vec3(1.0));
  struct Case {
    Json keys;
    std::string path, words;
  };
  const Case volumeCases[] = {
      {{{"file", nullptr}}, "objects[1].file", "missing"},
      {{{"file", ""}}, "objects[1].file", ""},
      {{{"file", 3}}, "objects[1].file", "string"},
      {{{"isovalue", nullptr}}, "objects[1].isovalue", "missing"},
      {{{"isovalue", "nan"}}, "objects[1].isovalue", "number"},
      {{{"isovalue", std::numeric_limits<double>::quiet_NaN()}}, "objects[1].isovalue", ""},
      {{{"material", "gold"}}, "objects[1].material", "unknown material"},
      {{{"type", "mesh"}}, "objects[1].type", "unknown object type"},
      {{{"vertices", Json::array()}}, "objects[1].vertices", "no 'vertices'"},
      {{{"transform", {{"scale", {0, 1, 1}}}}}, "objects[1].transform.scale", "zero"},
      {{{"id", "floor"}}, "objects[1].id", "duplicate"},
      {{{"file", "missing.nrrd"}}, "objects[1].file", "no such file"},
      {{{"file", "."}}, "objects[1].file", "no such file"},
  };
  for (const Case& c : volumeCases) {
    const ValidationError error = refusal(c.keys);
    EXPECT_EQ(error.path(), c.path) << c.keys.dump() << ": " << error.what();
    EXPECT_NE(std::string(error.what()).find(c.words), std::string::npos) << error.what();
  }
}

TEST_F(VolumeSceneTest, AVolumeInJsonWithoutFilesIsRefused) {
  writeNrrdVolume(path("blob.nrrd"), quantise8(sphereField(4)), Vec3(1.0));
  const Json scene = parseJsonText(
      [&] {
        std::ifstream in(writeScene(Json::object()));
        return std::string(std::istreambuf_iterator<char>(in), {});
      }(),
      kMaxJsonFileBytes, kMaxJsonDepth);
  try {
    sceneFromJson(scene);
    FAIL() << "a posted scene opened a file";
  } catch (const ValidationError& error) {
    EXPECT_EQ(error.path(), "objects[1].file");
    EXPECT_NE(std::string(error.what()).find("only from scene files"), std::string::npos);
  }
}

TEST_F(VolumeSceneTest, HostileFilesGiveClearErrors) {
  const std::string full(64, '\x40');
  struct Case {
    std::string name, text, words;
  };
  std::vector<Case> volumeCases = {
      {"truncated", nrrdHeader("uchar", "4 4 4", "raw") + full.substr(0, 10), "fread got only"},
      {"short-float", nrrdHeader("float", "4 4 4", "raw") + full, "fread got only"},
      {"gzip-garbage", nrrdHeader("uchar", "4 4 4", "gzip") + "this is not gzip at all", ""},
      {"int-type", nrrdHeader("int", "4 4 4", "raw") + full + full + full + full,
       "type 'int' is not supported"},
      {"unknown-type", nrrdHeader("quaternion", "4 4 4", "raw"), "type"},
      {"bzip2", nrrdHeader("uchar", "4 4 4", "bzip2"), "encoding 'bzip2' is not supported"},
      {"unknown-encoding", nrrdHeader("uchar", "4 4 4", "zip9"), "encoding"},
      {"two-d", "NRRD0004\ntype: uchar\ndimension: 2\nsizes: 8 8\nencoding: raw\n\n" + full,
       "dimension is 2"},
      {"thin", nrrdHeader("uchar", "1 8 8", "raw") + full, "at least 2 voxels"},
      {"sizes-mismatch",
       "NRRD0004\ntype: uchar\ndimension: 3\nsizes: 4 4\nencoding: raw\n\n" + full, "sizes"},
      {"huge", nrrdHeader("uchar", "4096 4096 4096", "raw"), "resource limit 'volume_voxels'"},
      {"huge-side", nrrdHeader("uchar", "100000 2 2", "raw"), "resource limit 'volume_side'"},
      {"detached", nrrdHeader("uchar", "4 4 4", "raw", "data file: /etc/hostname\n"),
       "detached data"},
      {"zero-spacing", nrrdHeader("uchar", "4 4 4", "raw", "spacings: 1 0 1\n") + full, "spacing"},
      {"not-nrrd", "hello, I am a text file\n", ""},
      {"empty", "", ""},
  };
  std::string nanFloats = nrrdHeader("float", "2 2 2", "raw");
  for (int k = 0; k < 8; ++k) {
    const float value = k == 5 ? std::numeric_limits<float>::quiet_NaN() : 1.0f;
    nanFloats.append(reinterpret_cast<const char*>(&value), sizeof value);
  }
  volumeCases.push_back({"nan-voxel", nanFloats, "voxel 5 is not a finite number"});
  for (const Case& c : volumeCases) {
    writeText(c.name + ".nrrd", c.text);
    const ValidationError error = refusal({{"file", c.name + ".nrrd"}});
    EXPECT_EQ(error.path(), "objects[1].file") << c.name;
    const std::string what = error.what();
    EXPECT_NE(what.find("'" + c.name + ".nrrd': "), std::string::npos) << what;
    EXPECT_NE(what.find(c.words), std::string::npos) << c.name << ": " << what;
    EXPECT_LT(what.size(), 400u) << what;  // one clear line, not Teem's whole stack
    if (std::getenv("PENUMBRA_PRINT_ERRORS")) std::printf("%s\n", what.c_str());
  }
}

}  // namespace
}  // namespace penumbra::protocol
