#include "server/data_directory.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace penumbra::server {

namespace {

namespace fs = std::filesystem;

std::string errnoText() { return std::strerror(errno); }

// The pid the lock holder wrote into the lock file ("" when unreadable).
std::string holderOf(int fd) {
  char buffer[32] = {};
  const ssize_t got = pread(fd, buffer, sizeof buffer - 1, 0);
  if (got <= 0) return "";
  std::string text(buffer, size_t(got));
  while (!text.empty() && (text.back() == '\n' || text.back() == ' ')) text.pop_back();
  return text;
}

void fsyncPath(const std::string& path, int flags) {
  const int fd = ::open(path.c_str(), flags | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open '" + path + "' to sync it: " + errnoText());
  const int synced = ::fsync(fd);
  const int error = errno;
  ::close(fd);
  if (synced != 0) throw std::runtime_error("cannot sync '" + path + "': " + std::strerror(error));
}

}  // namespace

DataDirectory::DataDirectory(const std::string& dir) {
  std::error_code error;
  fs::create_directories(dir, error);
  if (!fs::is_directory(dir))
    throw std::runtime_error("--data: cannot create directory '" + dir + "'");
  path_ = fs::absolute(dir).lexically_normal().string();
  while (path_.size() > 1 && path_.back() == '/') path_.pop_back();
  const std::string lockPath = (fs::path(path_) / "penumbra.lock").string();
  lockFd_ = ::open(lockPath.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (lockFd_ < 0)
    throw std::runtime_error("--data: cannot open '" + lockPath + "': " + errnoText());
  if (::flock(lockFd_, LOCK_EX | LOCK_NB) != 0) {
    const bool held = errno == EWOULDBLOCK;
    const std::string reason = errnoText();
    const std::string holder = holderOf(lockFd_);
    ::close(lockFd_);
    lockFd_ = -1;
    if (held)
      throw DataDirectoryLocked("--data: '" + path_ + "' is in use by another penumbra serve" +
                                (holder.empty() ? "" : " (pid " + holder + ")") +
                                ": one server per data directory");
    throw std::runtime_error("--data: cannot lock '" + lockPath + "': " + reason);
  }
  const std::string pid = std::to_string(::getpid()) + "\n";
  if (::ftruncate(lockFd_, 0) != 0 || ::pwrite(lockFd_, pid.data(), pid.size(), 0) < 0) {
    // The pid is only for the message a second server prints; the lock itself holds.
  }
  watch(path_);
}

DataDirectory::~DataDirectory() {
  if (lockFd_ >= 0) ::close(lockFd_);  // releases the lock
}

void DataDirectory::watch(const std::string& file) {
  struct stat info {};
  if (::stat(file.c_str(), &info) != 0)
    throw std::runtime_error("--data: cannot stat '" + file + "': " + errnoText());
  watched_.push_back({file, info.st_dev, info.st_ino});
}

std::string DataDirectory::problem() const {
  for (const Identity& identity : watched_) {
    struct stat info {};
    if (::stat(identity.path.c_str(), &info) != 0)
      return "'" + identity.path + "' is gone (" + errnoText() + ")";
    if (info.st_dev != identity.device || info.st_ino != identity.inode)
      return "'" + identity.path + "' was replaced by another file while the server ran";
  }
  if (::access(path_.c_str(), W_OK | X_OK) != 0)
    return "the data directory '" + path_ + "' is not writable (" + errnoText() + ")";
  return "";
}

void writeFileDurably(const std::string& path, std::string_view bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot create '" + path + "': " + errnoText());
  std::string failure;
  for (size_t done = 0; done < bytes.size() && failure.empty();) {
    const ssize_t wrote = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (wrote < 0 && errno != EINTR) failure = "cannot write '" + path + "': " + errnoText();
    if (wrote > 0) done += size_t(wrote);
  }
  if (failure.empty() && ::fsync(fd) != 0) failure = "cannot sync '" + path + "': " + errnoText();
  if (::close(fd) != 0 && failure.empty()) failure = "cannot close '" + path + "': " + errnoText();
  if (!failure.empty()) {
    ::unlink(path.c_str());  // a full disk leaves no empty or partial file
    throw std::runtime_error(failure);
  }
  try {
    fsyncPath(fs::path(path).parent_path().string(), O_RDONLY | O_DIRECTORY);
  } catch (...) {
    ::unlink(path.c_str());
    throw;
  }
}

}  // namespace penumbra::server
