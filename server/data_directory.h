// The data directory one server holds (docs/SERVER.md "Durability"): an exclusive lock on
// DIR/penumbra.lock (a second server on the same directory refuses to start), the identity of the
// directory and of the files it watches (the journal), so that a directory removed, replaced or
// made unwritable while serving is noticed before anything more is acknowledged, and durable
// writes (the file, then its directory, fsynced). Thread-safe: the checks are stat calls.
#pragma once

#include <sys/types.h>

#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace penumbra::server {

// Another process holds the lock: its message names the directory and that process's pid.
struct DataDirectoryLocked : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class DataDirectory {
 public:
  // Creates DIR when missing and locks it (flock, released when the process ends, kill -9
  // included). Throws DataDirectoryLocked, or std::runtime_error when DIR cannot be made or locked.
  explicit DataDirectory(const std::string& dir);
  ~DataDirectory();
  DataDirectory(const DataDirectory&) = delete;
  DataDirectory& operator=(const DataDirectory&) = delete;

  const std::string& path() const { return path_; }  // absolute, normalised
  // Remembers a file's identity (device, inode) now; problem() then checks it is still there.
  void watch(const std::string& file);
  // Empty while the directory is the one locked, still there and writable, and every watched
  // file still the one opened; else what is wrong, in words.
  std::string problem() const;

 private:
  struct Identity {
    std::string path;
    dev_t device = 0;
    ino_t inode = 0;
  };
  std::string path_;
  int lockFd_ = -1;
  std::vector<Identity> watched_;  // the directory first
};

// Writes `bytes` to `path` and makes it durable before returning: written, fsynced, closed, and
// its directory fsynced (so the name survives a power loss too). Throws std::runtime_error naming
// the path; a failed write leaves no file behind.
void writeFileDurably(const std::string& path, std::string_view bytes);

}  // namespace penumbra::server
