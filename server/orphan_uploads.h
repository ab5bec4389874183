// Uploaded volumes no journaled scene names. An upload is stored (and fsynced) before the frame
// that adds it commits; a kill in between leaves a file no acknowledged version uses, and nothing
// else would ever remove it. Swept once at start, before anything is served.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "server/scene_journal.h"

namespace penumbra::server {

// Whether `scene`'s source, one of its frames or one of its snapshots mentions `name` (an
// upload's file name, or its name relative to the data directory).
bool namesUpload(const SceneJournal::StoredScene& scene, const std::string& name);

// Removes the files of `uploadDir` named as uploads are (ID-<16 hex digits>.nrrd) that no
// scene source, frame or snapshot text of `scenes` mentions; returns how many. Removes nothing
// when some scene's frames could not all be read (a file might be named by an unread one).
size_t removeOrphanUploads(const std::string& uploadDir, const std::vector<SceneJournal::StoredScene>& scenes);

}  // namespace penumbra::server
