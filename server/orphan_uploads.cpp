#include "server/orphan_uploads.h"

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace penumbra::server {

namespace {

// storeUpload's names: a scene id, '-', 16 hex digits, ".nrrd".
bool looksLikeUpload(const std::string& name) {
  constexpr size_t kTail = 1 + 16 + 5;
  if (name.size() <= kTail || name.compare(name.size() - 5, 5, ".nrrd") != 0 || name[name.size() - kTail] != '-')
    return false;
  return std::all_of(name.end() - 21, name.end() - 5, [](char c) { return std::isxdigit(static_cast<unsigned char>(c)); });
}

bool mentioned(const std::string& name, const std::vector<SceneJournal::StoredScene>& scenes) {
  return std::any_of(scenes.begin(), scenes.end(),
                     [&](const auto& scene) { return namesUpload(scene, name); });
}

}  // namespace

bool namesUpload(const SceneJournal::StoredScene& scene, const std::string& name) {
  const auto in = [&](const std::string& text) { return text.find(name) != std::string::npos; };
  if (in(scene.source)) return true;
  for (const auto& frame : scene.frames)
    if (in(frame.frame)) return true;
  for (const auto& snapshot : scene.snapshots)
    if (in(snapshot.source)) return true;
  return false;
}

size_t removeOrphanUploads(const std::string& uploadDir, const std::vector<SceneJournal::StoredScene>& scenes) {
  if (std::any_of(scenes.begin(), scenes.end(), [](const auto& scene) { return !scene.complete; })) return 0;
  std::error_code error;
  size_t removed = 0;
  for (const auto& entry : std::filesystem::directory_iterator(uploadDir, error)) {
    const std::string name = entry.path().filename().string();
    if (!entry.is_regular_file(error) || !looksLikeUpload(name) || mentioned(name, scenes)) continue;
    if (std::filesystem::remove(entry.path(), error)) ++removed;
  }
  return removed;
}

}  // namespace penumbra::server
