#include "server/journaled_text.h"

#include <filesystem>

#include "protocol/json_text.h"
#include "protocol/scene_json.h"

namespace penumbra::server {

protocol::VolumeFiles journaledFiles(const std::string& dataDir) {
  protocol::VolumeFiles files;
  files.baseDirectory = dataDir;
  return files;
}

void relativeToDataDir(nlohmann::json& file, const std::string& dataDir) {
  const std::filesystem::path relative =
      std::filesystem::path(file.get<std::string>()).lexically_relative(dataDir);
  if (!relative.empty() && *relative.begin() != "..") file = relative.string();
}

std::string journaledSceneText(const Scene& scene, const std::string& dataDir) {
  nlohmann::json text = protocol::sceneToJson(scene);
  if (text.contains("objects"))
    for (nlohmann::json& object : text["objects"])
      if (object.value("type", "") == "volume") relativeToDataDir(object["file"], dataDir);
  return text.dump();
}

Scene sceneFromJournaledText(const std::string& text, const std::string& dataDir) {
  // Only scene files loaded by the operator and the server's own uploads can hold volumes:
  // reading them again is safe.
  const protocol::VolumeFiles files = journaledFiles(dataDir);
  return protocol::sceneFromJson(
      protocol::parseJsonText(text, text.size(), protocol::kMaxJsonDepth), &files);
}

Scene journaledScene(const Scene& scene, const std::string& dataDir) {
  Scene copy = sceneFromJournaledText(journaledSceneText(scene, dataDir), dataDir);
  std::vector<uint32_t> handles;
  for (size_t o = 0; o < scene.objects().size(); ++o) handles.push_back(scene.handleOf(o));
  copy.setHandles(std::move(handles), scene.nextHandle());
  return copy;
}

}  // namespace penumbra::server
