#include "protocol/material_json.h"

#include <array>
#include <string_view>

namespace penumbra::protocol {
namespace {

constexpr std::array<std::string_view, 4> kTypes = {"diffuse", "rough_diffuse", "conductor", "dielectric"};
constexpr double kMinRoughness = 1e-3, kMaxRoughness = 2.0;
constexpr double kMaxIor = 4.0;

// The index of value among names, or a ValidationError listing them.
size_t expectChoice(const Json& value, const std::string& path, const std::string& what,
                    std::initializer_list<std::string_view> names) {
  const std::string text = expectString(value, path);
  size_t i = 0;
  std::string list;
  for (std::string_view name : names) {
    if (text == name) return i;
    list += (i++ ? ", " : "") + std::string(name);
  }
  fail(path, "unknown " + what + " '" + text + "' (one of " + list + ")");
}

double expectRoughnessValue(const Json& value, const std::string& path) {
  const double a = expectNumber(value, path);
  if (a < kMinRoughness || a > kMaxRoughness)
    fail(path, "roughness " + shortNumber(a) + " is outside [" + shortNumber(kMinRoughness) + ", " +
                   shortNumber(kMaxRoughness) + "]");
  return a;
}

Vec2 expectRoughness(const Json& value, const std::string& path) {
  if (!value.is_array()) {
    const double a = expectRoughnessValue(value, path);
    return {a, a};
  }
  if (value.size() != 2) fail(path, "roughness needs a number or [alpha_x, alpha_y], got " + std::to_string(value.size()) + " values");
  return {expectRoughnessValue(value[0], indexPath(path, 0)), expectRoughnessValue(value[1], indexPath(path, 1))};
}

// Keys that only some types take: present on another type is an error (a typo in "type"
// would otherwise silently drop them).
void refuseKey(const Json& body, std::string_view key, const std::string& path, const std::string& types) {
  if (optionalKey(body, key)) fail(keyPath(path, key), "'" + std::string(key) + "' applies to " + types + " materials only");
}

}  // namespace

Material materialFromJson(const std::string& name, const Json& body, const std::string& path) {
  expectObject(body, path);
  Material m{name, {}};
  if (const Json* t = optionalKey(body, "type"))
    m.type = MaterialType(expectChoice(*t, keyPath(path, "type"), "material type",
                                       {kTypes[0], kTypes[1], kTypes[2], kTypes[3]}));
  const bool microfacet = m.type != MaterialType::Diffuse;
  // albedo: required where it is the reflectance; elsewhere only the irradiance view's colour.
  const bool needsAlbedo = m.type == MaterialType::Diffuse || m.type == MaterialType::RoughDiffuse;
  const std::string albedoPath = keyPath(path, "albedo");
  if (const Json* a = needsAlbedo ? &requireKey(body, "albedo", path) : optionalKey(body, "albedo")) {
    m.albedo = expectVec3(*a, albedoPath);
    for (int c = 0; c < 3; ++c)
      if (m.albedo[c] < 0 || m.albedo[c] > 1)
        fail(albedoPath, "albedo " + shortNumber(m.albedo[c]) + " is outside [0, 1]");
  }
  if (!microfacet) {
    for (std::string_view key : {"roughness", "ndf", "scattering"})
      refuseKey(body, key, path, "rough_diffuse, conductor and dielectric");
  }
  if (const Json* r = optionalKey(body, "roughness")) m.roughness = expectRoughness(*r, keyPath(path, "roughness"));
  if (const Json* n = optionalKey(body, "ndf"))
    m.ndf = expectChoice(*n, keyPath(path, "ndf"), "ndf", {"ggx", "beckmann"}) == 0 ? bsdf::Ndf::GGX : bsdf::Ndf::Beckmann;
  if (const Json* s = optionalKey(body, "scattering"))
    m.singleScattering = expectChoice(*s, keyPath(path, "scattering"), "scattering", {"multiple", "single"}) == 1;

  if (m.type != MaterialType::Conductor) {
    refuseKey(body, "eta", path, "conductor");
    refuseKey(body, "k", path, "conductor");
  }
  if (const Json* e = optionalKey(body, "eta")) {
    m.eta = expectVec3(*e, keyPath(path, "eta"));
    for (int c = 0; c < 3; ++c)
      if (!(m.eta[c] > 0)) fail(keyPath(path, "eta"), "eta " + shortNumber(m.eta[c]) + " is not positive");
  }
  if (const Json* k = optionalKey(body, "k")) {
    m.k = expectVec3(*k, keyPath(path, "k"));
    for (int c = 0; c < 3; ++c)
      if (m.k[c] < 0) fail(keyPath(path, "k"), "k " + shortNumber(m.k[c]) + " is negative");
  }
  if (m.type != MaterialType::Dielectric) refuseKey(body, "ior", path, "dielectric");
  if (const Json* i = optionalKey(body, "ior")) {
    m.ior = expectNumber(*i, keyPath(path, "ior"));
    if (!(m.ior > 1.0 && m.ior <= kMaxIor))
      fail(keyPath(path, "ior"), "ior " + shortNumber(m.ior) + " is outside (1, " + shortNumber(kMaxIor) + "]");
  }
  return m;
}

Json materialToJson(const Material& m) {
  Json out{{"albedo", toJson(m.albedo)}};
  if (m.type == MaterialType::Diffuse) return out;
  out["type"] = std::string(kTypes[size_t(m.type)]);
  out["roughness"] = m.roughness.x == m.roughness.y ? Json(m.roughness.x) : Json::array({m.roughness.x, m.roughness.y});
  out["ndf"] = m.ndf == bsdf::Ndf::GGX ? "ggx" : "beckmann";
  out["scattering"] = m.singleScattering ? "single" : "multiple";
  if (m.type == MaterialType::Conductor) {
    out["eta"] = toJson(m.eta);
    out["k"] = toJson(m.k);
  }
  if (m.type == MaterialType::Dielectric) out["ior"] = m.ior;
  return out;
}

}  // namespace penumbra::protocol
