// Material keys (docs/SCENE_FORMAT.md "Materials"): each type read with its keys and defaults,
// old albedo-only materials written back unchanged, every bad value refused with its key path.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "protocol/material_json.h"
#include "protocol/validation_error.h"

namespace penumbra::protocol {
namespace {

using json = nlohmann::json;

Material read(const json& body) { return materialFromJson("m", body, "materials.m"); }

// The key path of the error reading body, or "" when it is accepted.
std::string errorPath(const json& body) {
  try {
    read(body);
  } catch (const ValidationError& e) {
    return e.path();
  }
  return "";
}

TEST(MaterialJson, AlbedoOnlyStaysLambertianAndIsWrittenUnchanged) {
  const json body = {{"albedo", {0.7, 0.1, 0.1}}};
  const Material m = read(body);
  EXPECT_EQ(m.type, MaterialType::Diffuse);
  EXPECT_EQ(materialToJson(m), body);
}

TEST(MaterialJson, ReadsEachTypeWithItsKeys) {
  const Material c = read({{"type", "conductor"}, {"roughness", {0.3, 0.05}}, {"eta", {0.2, 0.4, 1.4}},
                           {"k", {3.6, 2.4, 1.8}}, {"ndf", "beckmann"}, {"scattering", "single"}});
  EXPECT_EQ(c.type, MaterialType::Conductor);
  EXPECT_EQ(c.roughness, Vec2(0.3, 0.05));
  EXPECT_EQ(c.eta, Vec3(0.2, 0.4, 1.4));
  EXPECT_EQ(c.k, Vec3(3.6, 2.4, 1.8));
  EXPECT_EQ(c.ndf, bsdf::Ndf::Beckmann);
  EXPECT_TRUE(c.singleScattering);
  const Material g = read({{"type", "dielectric"}, {"roughness", 0.1}, {"ior", 1.33}});
  EXPECT_EQ(g.type, MaterialType::Dielectric);
  EXPECT_EQ(g.roughness, Vec2(0.1));
  EXPECT_EQ(g.ior, 1.33);
  EXPECT_EQ(g.ndf, bsdf::Ndf::GGX);
  EXPECT_FALSE(g.singleScattering);
  const Material r = read({{"type", "rough_diffuse"}, {"albedo", {0.5, 0.5, 0.5}}, {"roughness", 1}});
  EXPECT_EQ(r.type, MaterialType::RoughDiffuse);
  for (const Material& m : {c, g, r}) EXPECT_TRUE(read(materialToJson(m)) == m);
}

TEST(MaterialJson, RefusesBadValuesWithKeyPaths) {
  const json conductor = {{"type", "conductor"}};
  auto with = [](json body, const char* key, json value) {
    body[key] = std::move(value);
    return body;
  };
  EXPECT_EQ(errorPath({{"albedo", {1, 1, 1}}, {"type", "metal"}}), "materials.m.type");
  EXPECT_EQ(errorPath({{"type", "rough_diffuse"}}), "materials.m.albedo");  // required there
  EXPECT_EQ(errorPath(conductor), "");                                      // not for a conductor
  EXPECT_EQ(errorPath(with(conductor, "roughness", 0)), "materials.m.roughness");
  EXPECT_EQ(errorPath(with(conductor, "roughness", 3)), "materials.m.roughness");
  EXPECT_EQ(errorPath(with(conductor, "roughness", {0.5, -1})), "materials.m.roughness[1]");
  EXPECT_EQ(errorPath(with(conductor, "roughness", {0.5, 0.5, 0.5})), "materials.m.roughness");
  EXPECT_EQ(errorPath(with(conductor, "roughness", "rough")), "materials.m.roughness");
  EXPECT_EQ(errorPath(with(conductor, "eta", {1, 0, 1})), "materials.m.eta");
  EXPECT_EQ(errorPath(with(conductor, "k", {1, -1, 1})), "materials.m.k");
  EXPECT_EQ(errorPath(with(conductor, "k", {1, 1})), "materials.m.k");
  EXPECT_EQ(errorPath(with(conductor, "ndf", "phong")), "materials.m.ndf");
  EXPECT_EQ(errorPath(with(conductor, "scattering", "double")), "materials.m.scattering");
  EXPECT_EQ(errorPath(with(conductor, "ior", 1.5)), "materials.m.ior");  // not a conductor's key
  EXPECT_EQ(errorPath({{"type", "dielectric"}, {"ior", 1.0}}), "materials.m.ior");
  EXPECT_EQ(errorPath({{"type", "dielectric"}, {"ior", 5}}), "materials.m.ior");
  EXPECT_EQ(errorPath({{"type", "dielectric"}, {"eta", {1, 1, 1}}}), "materials.m.eta");
  EXPECT_EQ(errorPath({{"albedo", {1, 1, 1}}, {"roughness", 0.5}}), "materials.m.roughness");
  EXPECT_EQ(errorPath({{"type", "dielectric"}, {"albedo", {2, 0, 0}}}), "materials.m.albedo");
}

}  // namespace
}  // namespace penumbra::protocol
