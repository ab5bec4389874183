// The binary mesh's one-channel parts (docs/API.md "Binary"): a part whose vertices are one colour
// scaled is sent as one value per vertex and a tint, else as r, g, b. Under two lights of different
// colours a part both light keeps three channels; on seeded random parts (proportional, grey,
// unrelated channels, zero, tiny, huge, nearly proportional) the encoder chooses as documented and
// every channel decodes (value times tint in f32, tests/server/binary_mesh_reader.h) within 2 f32
// ulps of its exact value, bit for bit where three channels are sent, alike in whole and value parts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "scenegen/cubes_scene.h"
#include "server/mesh_binary.h"
#include "server/scene_session.h"
#include "tests/server/binary_mesh_reader.h"

namespace penumbra::server {
namespace {

using test::BinaryMesh;
using test::parseBinary;
using test::withinTwoUlps;

// The spread of a part's chromaticity (each channel's share of r + g + b) over its vertices that
// some light reaches: 0 when every vertex is one colour scaled.
double chromaSpread(const std::vector<Vec3>& irradiance) {
  double spread = 0.0;
  for (int c = 0; c < 3; ++c) {
    double low = INFINITY, high = -INFINITY;
    for (const Vec3& e : irradiance) {
      const double sum = e.x + e.y + e.z;
      if (sum <= 0.0) continue;
      low = std::min(low, e[c] / sum);
      high = std::max(high, e[c] / sum);
    }
    if (high >= low) spread = std::max(spread, high - low);
  }
  return spread;
}

// Each decoded channel against the f32 value of its exact one: equal with three channels,
// within 2 ulps with one.
void expectDecodes(uint32_t channels, const std::vector<float>& decoded, const std::vector<Vec3>& exact) {
  ASSERT_EQ(decoded.size(), 3 * exact.size());
  for (size_t v = 0; v < exact.size(); ++v)
    for (int c = 0; c < 3; ++c) {
      const float sent = float(exact[v][c]);
      if (channels == 3) {
        ASSERT_EQ(decoded[3 * v + c], sent) << v << "," << c;
      } else {
        ASSERT_TRUE(withinTwoUlps(decoded[3 * v + c], sent))
            << v << "," << c << ": " << decoded[3 * v + c] << " for " << sent;
      }
    }
}

TEST(MeshTint, TwoLightsOfDifferentColoursKeepThreeChannelsWhereBothLightAPart) {
  CubesSceneOptions options;
  options.cubes = 8;
  options.seed = 4;
  options.twoLights = true;
  Scene scene = makeCubesScene(options);
  ASSERT_EQ(scene.lights().size(), 2u);
  const std::vector<Light> lights = scene.lights();
  scene.setLight(0, lights[0].polygon, Vec3(12, 10, 8));
  scene.setLight(1, lights[1].polygon, Vec3(3, 6, 11));
  SceneSession session("t", "two lights", scene);
  const auto s = session.snapshot();
  const MeshSelection all = s->select(std::nullopt);
  const BinaryMesh whole = parseBinary(mesh_binary::encode(*s, all));
  ASSERT_EQ(whole.parts.size(), all.parts.size());
  size_t mixed = 0, single = 0;
  for (size_t k = 0; k < all.parts.size(); ++k) {
    const std::vector<Vec3>& exact = s->parts[all.parts[k]].mesh->irradiance;
    const BinaryMesh::Part& part = whole.parts[k];
    SCOPED_TRACE("part " + std::to_string(k));
    const double spread = chromaSpread(exact);
    if (spread > 1e-3) {  // both lights: their mix varies over the part
      EXPECT_EQ(part.channels, 3u);
      ++mixed;
    } else if (spread < 1e-12) {  // one colour: one light, or none
      EXPECT_EQ(part.channels, 1u);
      ++single;
    }
    expectDecodes(part.channels, part.irradiance, exact);
    if (HasFailure()) return;
  }
  EXPECT_GT(mixed, 0u);
  EXPECT_GT(single, 0u);
}

// A part's irradiance of one kind, `vertices` long.
enum class Kind { Proportional, Grey, Unrelated, Zero, Tiny, Huge, NearlyProportional, Count };

std::vector<Vec3> randomIrradiance(Kind kind, size_t vertices, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto exp10 = [&](double low, double high) { return std::pow(10.0, low + (high - low) * unit(rng)); };
  // A colour, now and then with a channel at zero.
  Vec3 colour(unit(rng) + 0.01, unit(rng) + 0.01, unit(rng) + 0.01);
  if (rng() % 4 == 0) colour[rng() % 3] = 0.0;
  std::vector<Vec3> out;
  for (size_t v = 0; v < vertices; ++v) {
    const bool dark = rng() % 8 == 0;  // a vertex in umbra
    switch (kind) {
      case Kind::Proportional:
      case Kind::NearlyProportional:
        out.push_back(dark ? Vec3(0.0) : colour * exp10(-3, 3));
        break;
      case Kind::Grey:
        out.push_back(Vec3(dark ? 0.0 : exp10(-3, 3)));
        break;
      case Kind::Unrelated:  // (and a second vertex: one alone is its own colour)
        if (v == 0) out.push_back(Vec3(unit(rng), unit(rng), unit(rng)) * 100.0);
        out.push_back(Vec3(unit(rng), unit(rng), unit(rng)) * 100.0);
        break;
      case Kind::Zero:
        out.push_back(Vec3(0.0));
        break;
      case Kind::Tiny:  // down to f32's subnormals and below
        out.push_back(dark ? Vec3(0.0) : colour * exp10(-48, -36));
        break;
      case Kind::Huge:  // up to f32's largest, now and then past it
        out.push_back(dark ? Vec3(0.0) : colour * exp10(30, rng() % 16 == 0 ? 40 : 37));
        break;
      case Kind::Count:
        break;
    }
  }
  if (kind == Kind::NearlyProportional) {  // two lit vertices, one's channel ~100 f32 ulps off
    int brightest = 0;
    for (int c = 1; c < 3; ++c)
      if (colour[c] > colour[brightest]) brightest = c;
    const int other = (brightest + 1 + int(rng() % 2)) % 3;
    out.push_back(colour * exp10(-3, 3));
    Vec3 e = colour * exp10(-3, 3);
    e[other] = e[other] > 0.0 ? e[other] * (1.0 + 1e-5) : e[brightest] * 1e-3;
    out.insert(out.begin() + long(rng() % out.size()), e);
  }
  return out;
}

TEST(MeshTint, RandomPartsChooseTheirChannelsAndDecodeWithinTwoUlps) {
  std::mt19937_64 rng(35);
  SceneSnapshot s;
  s.version = 2;
  std::vector<Kind> kinds;
  for (int i = 0; i < 1400; ++i) {
    const Kind kind = Kind(i % int(Kind::Count));
    auto mesh = std::make_shared<ReceiverMesh>();
    mesh->irradiance = randomIrradiance(kind, 1 + rng() % 40, rng);
    mesh->positions.assign(mesh->irradiance.size(), Vec3(0.0));
    mesh->classes.assign(mesh->irradiance.size(), LightClass::Lit);
    s.parts.push_back(MeshPart{PartKey{ReceiverKey{"object", uint32_t(i)}, 0, 0}, mesh, 2, 1});
    kinds.push_back(kind);
  }
  MeshSelection wholeSelection, valueSelection;
  valueSelection.since = 1;
  for (size_t i = 0; i < s.parts.size(); ++i) wholeSelection.parts.push_back(i), valueSelection.valueParts.push_back(i);
  const BinaryMesh whole = parseBinary(mesh_binary::encode(s, wholeSelection));
  const BinaryMesh values = parseBinary(mesh_binary::encode(s, valueSelection));
  ASSERT_EQ(whole.parts.size(), s.parts.size());
  ASSERT_EQ(values.valueParts.size(), s.parts.size());
  size_t tinyOneChannel = 0;
  for (size_t i = 0; i < s.parts.size(); ++i) {
    const std::vector<Vec3>& exact = s.parts[i].mesh->irradiance;
    const BinaryMesh::Part& part = whole.parts[i];
    const BinaryMesh::ValuePart& value = values.valueParts[i];
    SCOPED_TRACE("part " + std::to_string(i) + " of kind " + std::to_string(int(kinds[i])));
    const bool finite = std::all_of(exact.begin(), exact.end(), [](const Vec3& e) {
      return std::isfinite(float(e.x)) && std::isfinite(float(e.y)) && std::isfinite(float(e.z));
    });
    switch (kinds[i]) {
      case Kind::Proportional:
        EXPECT_EQ(part.channels, 1u);
        EXPECT_EQ(*std::max_element(part.tint, part.tint + 3), 1.0f);
        break;
      case Kind::Grey:
      case Kind::Zero:
        EXPECT_EQ(part.channels, 1u);
        for (float t : part.tint) EXPECT_EQ(t, 1.0f);
        for (size_t k = 0; k < part.irradiance.size(); ++k)  // bit for bit
          EXPECT_EQ(part.irradiance[k], float(exact[k / 3][k % 3]));
        break;
      case Kind::Huge:
        if (finite) {
          EXPECT_EQ(part.channels, 1u);
        }
        break;
      case Kind::Unrelated:
      case Kind::NearlyProportional:
        EXPECT_EQ(part.channels, 3u);
        break;
      case Kind::Tiny:  // either: subnormal values lose the precision a tint needs
        tinyOneChannel += part.channels == 1;
        break;
      case Kind::Count:
        break;
    }
    if (part.channels == 3) {
      for (float t : part.tint) EXPECT_EQ(t, 1.0f);
    }
    expectDecodes(part.channels, part.irradiance, exact);
    // A value part sends what a whole part does.
    EXPECT_EQ(value.channels, part.channels);
    EXPECT_TRUE(std::equal(value.tint, value.tint + 3, part.tint));
    EXPECT_EQ(value.irradiance, part.irradiance);
    if (HasFailure()) return;
  }
  EXPECT_GT(tinyOneChannel, 0u);  // normal-range tiny values still fit one channel
}

}  // namespace
}  // namespace penumbra::server
