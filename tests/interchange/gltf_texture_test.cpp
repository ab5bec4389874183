// glTF base colour textures folded into the albedo (issue 40, texture_average.h): a textured
// primitive's albedo is its base colour factor times the texture's linear colour averaged over
// its faces, stated in the report; skins, animations and morph targets are ignored with a note.
#include <gtest/gtest.h>

#include <cmath>

#include "gltf_test_models.h"
#include "interchange/scene_import.h"

namespace penumbra::interchange {
namespace {

double linear(double srgb) {
  return srgb <= 0.04045 ? srgb / 12.92 : std::pow((srgb + 0.055) / 1.055, 2.4);
}

// A 2 × 2 RGB image: left column `left`, right column `right` (8-bit sRGB).
int addImage(ModelWriter& w, const std::array<unsigned char, 3>& left,
             const std::array<unsigned char, 3>& right) {
  tinygltf::Image image;
  image.width = 2, image.height = 2, image.component = 3, image.bits = 8;
  image.pixel_type = TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE;
  image.mimeType = "image/png";  // the writer embeds it as a PNG data URI
  for (int row = 0; row < 2; ++row)
    for (const auto& texel : {left, right})
      image.image.insert(image.image.end(), texel.begin(), texel.end());
  w.model().images.push_back(image);
  tinygltf::Texture texture;
  texture.source = int(w.model().images.size() - 1);
  w.model().textures.push_back(texture);
  return int(w.model().textures.size() - 1);
}

// A 1 m square at height y with UVs from (0, 0) to (uMax, 1); no UVs when uMax is 0.
void texturedQuad(ModelWriter& w, const std::string& name, int material, double y, double uMax) {
  const std::vector<float> xyz = {-0.5f, float(y), -0.5f, -0.5f, float(y), 0.5f,
                                  0.5f,  float(y), 0.5f,  0.5f,  float(y), -0.5f};
  const std::vector<float> uv = {0, 0, 0, 1, float(uMax), 1, float(uMax), 0};
  const std::vector<uint16_t> indices = {0, 1, 2, 0, 2, 3};
  tinygltf::Primitive p;
  p.material = material;
  p.attributes["POSITION"] =
      w.accessor(xyz.data(), xyz.size() * 4, 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  if (uMax > 0)
    p.attributes["TEXCOORD_0"] =
        w.accessor(uv.data(), uv.size() * 4, 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2);
  p.indices = w.accessor(indices.data(), 12, 6, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                         TINYGLTF_TYPE_SCALAR);
  w.node(name, p);
}

Vec3 albedoOf(const ImportResult& result, const std::string& object) {
  const auto index = result.scene.findObject(object);
  EXPECT_TRUE(index) << object;
  return index ? result.scene.albedo(FaceId{result.scene.handleOf(*index), 0}) : Vec3(-1.0);
}

TEST(GltfTexture, BaseColourTextureIsAveragedIntoTheAlbedo) {
  ModelWriter w = roomWriter();
  const int texture = addImage(w, {255, 0, 0}, {0, 0, 255});
  const int material = w.material("painted", {0.5, 1, 1}, {0, 0, 0}, 1);
  w.model().materials[size_t(material)].pbrMetallicRoughness.baseColorTexture.index = texture;
  texturedQuad(w, "left_half", material, 1, 0.5);  // only the red column
  texturedQuad(w, "whole", material, 1.5, 1);      // half red, half blue
  texturedQuad(w, "no_uvs", material, 2, 0);
  const ImportResult result = importSceneBytes(w.write(true), "textured.glb", {}, {});

  const Vec3 left = albedoOf(result, "left_half");
  EXPECT_DOUBLE_EQ(left.x, 0.5);  // factor 0.5 × linear red 1
  EXPECT_DOUBLE_EQ(left.y, 0);
  EXPECT_DOUBLE_EQ(left.z, 0);
  // Half of each colour, within the sampling of a 2-texel-wide image (n = 3 per triangle).
  const Vec3 whole = albedoOf(result, "whole");
  EXPECT_NEAR(whole.x, 0.5 * 0.5, 0.05);
  EXPECT_NEAR(whole.z, 0.5, 0.1);
  EXPECT_DOUBLE_EQ(whole.y, 0);
  EXPECT_EQ(albedoOf(result, "no_uvs"), Vec3(0.5, 1, 1));  // the factor alone
  EXPECT_EQ(result.report.repaired("textures_averaged_into_albedo"), 2u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("textures_ignored"), 1u) << result.report.summary();
  EXPECT_NE(result.report.summary().find(
                "'left_half': base colour texture averaged over its faces: albedo (0.5, 0, 0)"),
            std::string::npos)
      << result.report.summary();
  EXPECT_NEAR(linear(0.5), 0.214,
              1e-3);  // the sRGB decoding the averages use (sanity of the helper)
}

TEST(GltfTexture, SkinsAnimationsAndMorphTargetsAreIgnoredWithANote) {
  ModelWriter w = roomWriter();
  tinygltf::Skin skin;
  skin.joints = {0};
  w.model().skins.push_back(skin);
  const std::vector<float> times = {0, 1}, moves = {0, 0, 0, 0, 1, 0};
  tinygltf::AnimationSampler sampler;
  sampler.input =
      w.accessor(times.data(), 8, 2, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR);
  w.model().accessors.back().minValues = {0};
  w.model().accessors.back().maxValues = {1};
  sampler.output =
      w.accessor(moves.data(), 24, 2, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3);
  tinygltf::AnimationChannel channel;
  channel.sampler = 0;
  channel.target_node = 0;
  channel.target_path = "translation";
  tinygltf::Animation animation;
  animation.samplers.push_back(sampler);
  animation.channels.push_back(channel);
  w.model().animations.push_back(animation);
  const std::vector<float> offsets(12, 0.5f);  // a morph target moving the floor's corners up
  w.model().meshes[0].primitives[0].targets.push_back(
      {{"POSITION",
        w.accessor(offsets.data(), 48, 4, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3)}});
  const ImportResult result = importSceneBytes(w.write(true), "animated.glb", {}, {});
  EXPECT_EQ(result.report.repaired("skins_ignored"), 1u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("animations_ignored"), 1u) << result.report.summary();
  EXPECT_EQ(result.report.repaired("morph_targets_ignored"), 1u) << result.report.summary();
  EXPECT_NE(result.report.summary().find("animations ignored"), std::string::npos)
      << result.report.summary();
  // The floor stays where its node puts it: y = 0, not moved by the animation or the target.
  EXPECT_EQ(result.scene.bounds().min.y, 0);
}

}  // namespace
}  // namespace penumbra::interchange
