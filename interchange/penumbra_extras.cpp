#include "interchange/penumbra_extras.h"

namespace penumbra::interchange {

tinygltf::Value toGltfValue(const nlohmann::json& json) {
  switch (json.type()) {
    case nlohmann::json::value_t::boolean:
      return tinygltf::Value(json.get<bool>());
    case nlohmann::json::value_t::number_integer:
    case nlohmann::json::value_t::number_unsigned:
      return tinygltf::Value(json.get<int>());
    case nlohmann::json::value_t::number_float:
      return tinygltf::Value(json.get<double>());
    case nlohmann::json::value_t::string:
      return tinygltf::Value(json.get<std::string>());
    case nlohmann::json::value_t::array: {
      tinygltf::Value::Array array;
      for (const nlohmann::json& item : json) array.push_back(toGltfValue(item));
      return tinygltf::Value(std::move(array));
    }
    case nlohmann::json::value_t::object: {
      tinygltf::Value::Object object;
      for (const auto& [key, item] : json.items()) object[key] = toGltfValue(item);
      return tinygltf::Value(std::move(object));
    }
    default:
      return tinygltf::Value();
  }
}

nlohmann::json toJson(const tinygltf::Value& value) {
  if (value.IsBool()) return value.Get<bool>();
  if (value.IsInt()) return value.Get<int>();
  if (value.IsNumber()) return value.GetNumberAsDouble();
  if (value.IsString()) return value.Get<std::string>();
  if (value.IsArray()) {
    nlohmann::json array = nlohmann::json::array();
    for (size_t i = 0; i < value.ArrayLen(); ++i) array.push_back(toJson(value.Get(int(i))));
    return array;
  }
  if (value.IsObject()) {
    nlohmann::json object = nlohmann::json::object();
    for (const std::string& key : value.Keys()) object[key] = toJson(value.Get(key));
    return object;
  }
  return nullptr;
}

nlohmann::json penumbraExtras(const tinygltf::Value& extras) {
  if (!extras.IsObject() || !extras.Has(kPenumbraExtras)) return nullptr;
  return toJson(extras.Get(kPenumbraExtras));
}

}  // namespace penumbra::interchange
