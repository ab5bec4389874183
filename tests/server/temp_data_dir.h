// A data directory for durable-server tests (the journal): fresh and empty, removed at scope exit.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <string>

#include "server_fixture.h"

namespace penumbra::server::test {

class TempDataDir {
 public:
  TempDataDir() {
    path_ = std::filesystem::temp_directory_path() /
            ("penumbra-journal-test-" + std::to_string(getpid()) + "-" + std::to_string(counter_++));
    std::filesystem::remove_all(path_);
  }
  ~TempDataDir() { std::filesystem::remove_all(path_); }
  TempDataDir(const TempDataDir&) = delete;
  TempDataDir& operator=(const TempDataDir&) = delete;
  std::string str() const { return path_.string(); }

  // Loopback server options journaling to this directory.
  ServerOptions durable() const {
    ServerOptions options = RunningServer::loopback();
    options.dataDir = str();
    return options;
  }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

}  // namespace penumbra::server::test
