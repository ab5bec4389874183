// Scenes and frames as the journal keeps them (scene_journal.h): JSON in which the files under
// the data directory (uploaded volumes) are named relative to it, so the directory may move, and
// read back against it. Free functions; thread-safe.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "core/scene/scene.h"
#include "protocol/volume_json.h"

namespace penumbra::server {

// The files a journaled text names, resolved against `dataDir` (older journals' absolute
// paths stay as they are).
protocol::VolumeFiles journaledFiles(const std::string& dataDir);
// Rewrites a volume's "file" under `dataDir` relative to it; others are left as resolved.
void relativeToDataDir(nlohmann::json& file, const std::string& dataDir);
// Scene JSON v1 of `scene` with its volumes' files relative to `dataDir`.
std::string journaledSceneText(const Scene& scene, const std::string& dataDir);
// The scene a journaled text holds; throws (protocol's errors) when it does not load.
Scene sceneFromJournaledText(const std::string& text, const std::string& dataDir);
// `scene` read back from its journaled text, with its object handles: what a snapshot of it
// restores, so what the server builds when it takes one (SceneSession::rebase) and a replay
// where the server did.
Scene journaledScene(const Scene& scene, const std::string& dataDir);

}  // namespace penumbra::server
