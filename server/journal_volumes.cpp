// SceneJournal's uploaded volume files (scene_journal.h): kept by the store with their scene, so
// that any node serving the journal finds them; each node keeps a copy in its data directory,
// where the scene's texts name them (relative to it) and the engine reads them.
#include <zlib.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <optional>
#include <vector>

#include "server/data_directory.h"
#include "server/orphan_uploads.h"
#include "server/scene_journal.h"

namespace penumbra::server {

namespace {

// The journal's texts name uploads "volumes/FILE": nothing else is ever read or written here.
void requireUploadName(const std::string& name) {
  const std::string prefix = "volumes/";
  const std::string file = name.substr(std::min(name.size(), prefix.size()));
  if (name.rfind(prefix, 0) != 0 || file.empty() || file == "." || file == ".." ||
      file.find('/') != std::string::npos)
    throw std::runtime_error("'" + name + "' is not an uploaded volume's name (volumes/FILE)");
}

// The CRC-32 of the file at `path` when it is `size` bytes long; nullopt when it is missing or
// of another size.
std::optional<uint32_t> fileChecksum(const std::string& path, int64_t size) {
  std::error_code error;
  const auto found = std::filesystem::file_size(path, error);
  if (error || int64_t(found) != size) return std::nullopt;
  std::ifstream in(path, std::ios::binary);
  std::vector<char> block(size_t(1) << 20);
  uLong crc = crc32_z(0, nullptr, 0);
  while (in) {
    in.read(block.data(), std::streamsize(block.size()));
    crc = crc32_z(crc, reinterpret_cast<const Bytef*>(block.data()), size_t(in.gcount()));
  }
  if (in.bad()) return std::nullopt;
  return uint32_t(crc);
}

// This node's copy of an upload (its folder made on first use).
void writeCopy(const std::string& path, const std::string& bytes) {
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  std::filesystem::remove(path);  // a damaged copy (writeFileDurably creates a new file)
  writeFileDurably(path, bytes);
}

}  // namespace

uint32_t SceneJournal::volumeChecksum(const std::string& bytes) {
  return uint32_t(crc32_z(0, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size()));
}

void SceneJournal::addVolume(int64_t key, const std::string& name, const std::string& bytes) {
  requireUploadName(name);
  std::lock_guard lock(mutex_);
  if (!lastVersion_.count(key)) throw std::runtime_error("the scene is no longer journaled");
  requireDurable();
  const uint32_t crc = volumeChecksum(bytes);
  store_->putVolume({key, name, bytes, int64_t(bytes.size()), int64_t(crc)}, leaseOf(key));
  // This node's copy (SQLite's store keeps the bytes there itself).
  const std::string copy = (std::filesystem::path(dir_->path()) / name).string();
  if (fileChecksum(copy, int64_t(bytes.size())) != crc) writeCopy(copy, bytes);
}

void SceneJournal::removeVolume(int64_t key, const std::string& name) {
  requireUploadName(name);
  std::lock_guard lock(mutex_);
  std::error_code ignored;
  try {
    store_->deleteVolume(key, name, leaseOf(key));
  } catch (...) {  // the copy goes anyway: no text names it
    std::filesystem::remove(std::filesystem::path(dir_->path()) / name, ignored);
    throw;
  }
  std::filesystem::remove(std::filesystem::path(dir_->path()) / name, ignored);
}

std::string SceneJournal::fetchVolumes(const StoredScene& scene) {
  std::lock_guard lock(mutex_);
  try {
    requireReachable();
    for (const JournalVolumeRow& row : store_->volumesOf(scene.key)) {
      if (!namesUpload(scene, row.name)) continue;  // stored, then its frame was never acknowledged
      requireUploadName(row.name);
      const std::string copy = (std::filesystem::path(dir_->path()) / row.name).string();
      if (fileChecksum(copy, row.size) == uint32_t(row.crc)) continue;  // this node's copy
      const std::optional<JournalVolumeRow> stored = store_->readVolume(scene.key, row.name);
      if (!stored) throw std::runtime_error("the uploaded volume " + row.name + " is gone");
      if (int64_t(stored->bytes.size()) != row.size ||
          volumeChecksum(stored->bytes) != uint32_t(row.crc))
        throw std::runtime_error("the uploaded volume " + row.name +
                                 " fails its checksum (damaged in the journal)");
      writeCopy(copy, stored->bytes);
    }
  } catch (const std::exception& error) {
    return std::string("its uploaded volumes cannot be fetched: ") + error.what();
  }
  return "";
}

}  // namespace penumbra::server
