// Typed, path-tracking access to untrusted JSON values: every accessor either
// returns the value or throws ValidationError naming the key path and what was
// wrong. Free functions over const json; thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "core/geom/vec.h"

namespace penumbra::protocol {

using Json = nlohmann::json;

// Key paths: "a.b", "a[3]"; the root is "". Keys that are not plain
// identifiers are quoted: materials["dark grey"].
std::string keyPath(const std::string& parent, std::string_view key);
std::string indexPath(const std::string& parent, size_t index);

// "object", "array", "string", "number", "boolean", "null".
const char* jsonTypeName(const Json& value);

[[noreturn]] void fail(const std::string& path, const std::string& problem);

const Json& expectObject(const Json& value, const std::string& path);
const Json& expectArray(const Json& value, const std::string& path);
std::string expectString(const Json& value, const std::string& path);
// Non-empty string (ids, names).
std::string expectName(const Json& value, const std::string& path);
bool expectBool(const Json& value, const std::string& path);
// A finite number.
double expectNumber(const Json& value, const std::string& path);
// An integral number in [0, limit) (an index); JSON 2.0 counts as 2.
uint32_t expectIndex(const Json& value, const std::string& path, size_t limit);
// An array of exactly 3 finite numbers.
Vec3 expectVec3(const Json& value, const std::string& path);

// object[key], or a "missing required key" error at keyPath(path, key).
const Json& requireKey(const Json& object, std::string_view key, const std::string& path);
// object[key], or nullptr when absent. The object must already be checked.
const Json* optionalKey(const Json& object, std::string_view key);

// Checks "format" and "version" of a document root.
void expectHeader(const Json& root, std::string_view format, int version);

// Number formatting for messages (3 significant digits: "0.00234", "1.5").
std::string shortNumber(double value);

Json toJson(const Vec3& v);

}  // namespace penumbra::protocol
