#include "protocol/json_reader.h"

#include <cctype>
#include <cmath>
#include <cstdio>

#include "protocol/validation_error.h"

namespace penumbra::protocol {

namespace {

bool isIdentifier(std::string_view key) {
  if (key.empty() || std::isdigit(static_cast<unsigned char>(key.front()))) return false;
  for (char c : key)
    if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-')) return false;
  return true;
}

// Describes a value briefly for "expected X, got Y" messages.
std::string describe(const Json& value) {
  if (value.is_string()) {
    std::string s = value.get_ref<const std::string&>();
    if (s.size() > 40) s = s.substr(0, 40) + "...";
    return "string '" + s + "'";
  }
  if (value.is_number() || value.is_boolean() || value.is_null()) return value.dump();
  return jsonTypeName(value);
}

}  // namespace

std::string keyPath(const std::string& parent, std::string_view key) {
  if (isIdentifier(key)) return parent.empty() ? std::string(key) : parent + "." + std::string(key);
  return parent + "[" + Json(std::string(key)).dump(-1, ' ', false, Json::error_handler_t::replace) + "]";
}

std::string indexPath(const std::string& parent, size_t index) {
  return parent + "[" + std::to_string(index) + "]";
}

const char* jsonTypeName(const Json& value) {
  switch (value.type()) {
    case Json::value_t::object: return "object";
    case Json::value_t::array: return "array";
    case Json::value_t::string: return "string";
    case Json::value_t::boolean: return "boolean";
    case Json::value_t::null: return "null";
    case Json::value_t::number_integer:
    case Json::value_t::number_unsigned:
    case Json::value_t::number_float: return "number";
    default: return "unsupported value";
  }
}

void fail(const std::string& path, const std::string& problem) { throw ValidationError(path, problem); }

const Json& expectObject(const Json& value, const std::string& path) {
  if (!value.is_object()) fail(path, std::string("expected an object, got ") + describe(value));
  return value;
}

const Json& expectArray(const Json& value, const std::string& path) {
  if (!value.is_array()) fail(path, std::string("expected an array, got ") + describe(value));
  return value;
}

std::string expectString(const Json& value, const std::string& path) {
  if (!value.is_string()) fail(path, std::string("expected a string, got ") + describe(value));
  return value.get<std::string>();
}

std::string expectName(const Json& value, const std::string& path) {
  std::string name = expectString(value, path);
  if (name.empty()) fail(path, "expected a non-empty string");
  return name;
}

bool expectBool(const Json& value, const std::string& path) {
  if (!value.is_boolean()) fail(path, std::string("expected true or false, got ") + describe(value));
  return value.get<bool>();
}

double expectNumber(const Json& value, const std::string& path) {
  if (!value.is_number()) fail(path, std::string("expected a number, got ") + describe(value));
  const double x = value.get<double>();
  // The parser refuses overflowing literals, but a Json built in code may hold
  // inf or NaN.
  if (!std::isfinite(x)) fail(path, "number is not finite");
  return x;
}

uint32_t expectIndex(const Json& value, const std::string& path, size_t limit) {
  if (!value.is_number()) fail(path, std::string("expected an index, got ") + describe(value));
  if (value.is_number_integer()) {  // signed or unsigned
    if (!value.is_number_unsigned() && value.get<int64_t>() < 0)
      fail(path, "index " + value.dump() + " is out of range (negative)");
    const uint64_t i = value.get<uint64_t>();
    if (i >= limit)
      fail(path, "index " + std::to_string(i) + " is out of range (there are " +
                     std::to_string(limit) + ")");
    return uint32_t(i);
  }
  const double x = value.get<double>();
  if (!std::isfinite(x) || x != std::floor(x))
    fail(path, "index " + value.dump() + " is not an integer");
  if (x < 0 || x >= double(limit))
    fail(path, "index " + value.dump() + " is out of range (there are " + std::to_string(limit) + ")");
  return uint32_t(x);
}

Vec3 expectVec3(const Json& value, const std::string& path) {
  if (!value.is_array() || value.size() != 3)
    fail(path, std::string("expected [x, y, z] (3 numbers), got ") +
                   (value.is_array() ? "an array of " + std::to_string(value.size()) : describe(value)));
  return Vec3(expectNumber(value[0], indexPath(path, 0)), expectNumber(value[1], indexPath(path, 1)),
              expectNumber(value[2], indexPath(path, 2)));
}

const Json& requireKey(const Json& object, std::string_view key, const std::string& path) {
  const auto it = object.find(std::string(key));
  if (it == object.end()) fail(keyPath(path, key), "missing required key '" + std::string(key) + "'");
  return *it;
}

const Json* optionalKey(const Json& object, std::string_view key) {
  const auto it = object.find(std::string(key));
  return it == object.end() ? nullptr : &*it;
}

void expectHeader(const Json& root, std::string_view format, int version) {
  expectObject(root, "");
  const std::string name = expectString(requireKey(root, "format", ""), "format");
  if (name != format)
    fail("format", "expected \"" + std::string(format) + "\", got \"" + name + "\"");
  const Json& v = requireKey(root, "version", "");
  if (!v.is_number()) fail("version", std::string("expected a number, got ") + describe(v));
  if (!(v.is_number_integer() && v.get<int64_t>() == version))
    fail("version", "unsupported version " + v.dump() + " (this reader knows version " +
                        std::to_string(version) + ")");
}

std::string shortNumber(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

Json toJson(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

}  // namespace penumbra::protocol
