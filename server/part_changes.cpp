#include "server/part_changes.h"

#include <stdexcept>

namespace penumbra::server {

using nlohmann::json;

namespace {

json keysJson(const std::vector<PartKey>& keys) {
  json out = json::array();
  for (const PartKey& key : keys) out.push_back({key.receiver.object, key.receiver.face, key.x, key.y});
  return out;
}

std::vector<PartKey> keysFrom(const json& list) {
  std::vector<PartKey> out;
  for (const json& key : list) {
    if (!key.is_array() || key.size() != 4) throw std::runtime_error("a part key is not [object, face, x, y]");
    out.push_back({{key[0].get<std::string>(), key[1].get<uint32_t>()}, key[2].get<int64_t>(),
                   key[3].get<int64_t>()});
  }
  return out;
}

}  // namespace

PartChanges partChangesOf(const SceneSnapshot& next) {
  PartChanges changes;
  for (const MeshPart& part : next.parts)
    if (part.version == next.version)
      (part.shapeVersion == next.version ? changes.changed : changes.values).push_back(part.key);
  for (const auto& [key, version] : next.removed)
    if (version == next.version) changes.removed.push_back(key);
  return changes;
}

std::string partChangesText(const PartChanges& changes) {
  return json{{"changed", keysJson(changes.changed)},
              {"removed", keysJson(changes.removed)},
              {"values", keysJson(changes.values)}}
      .dump();
}

PartChanges partChangesFromText(const std::string& text) {
  try {
    const json doc = json::parse(text);
    return {keysFrom(doc.at("changed")), keysFrom(doc.at("removed")),
            doc.contains("values") ? keysFrom(doc.at("values")) : std::vector<PartKey>{}};
  } catch (const json::exception& error) {
    throw std::runtime_error(std::string("journaled part changes unreadable: ") + error.what());
  }
}

}  // namespace penumbra::server
