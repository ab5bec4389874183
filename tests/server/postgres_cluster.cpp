#include "postgres_cluster.h"

#include <gtest/gtest.h>
#include <libpq-fe.h>
#include <pwd.h>
#include <signal.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace penumbra::server::test {

namespace {

namespace fs = std::filesystem;

constexpr const char* kBin = "/usr/lib/postgresql/15/bin";  // Debian's postgresql-15
constexpr const char* kSuperuser = "penumbra";              // the cluster's, whoever runs it

// Runs `command` (no shell quoting needed: our paths have no spaces) as the cluster's owner.
int runAsOwner(const std::string& command) {
  const std::string line = geteuid() == 0 ? "runuser -u postgres -- " + command : command;
  return std::system((line + " >/dev/null 2>&1").c_str());
}

std::string fileText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Stops the cluster when the test binary ends (after every test, before static destructors).
class ClusterTeardown : public ::testing::Environment {
 public:
  void TearDown() override { cluster.reset(); }
  static inline std::unique_ptr<PostgresCluster> cluster;
};

const auto* registered = ::testing::AddGlobalTestEnvironment(new ClusterTeardown);

}  // namespace

PostgresCluster& PostgresCluster::shared() {
  if (!ClusterTeardown::cluster) ClusterTeardown::cluster.reset(new PostgresCluster());
  return *ClusterTeardown::cluster;
}

PostgresCluster::PostgresCluster() {
  (void)registered;
  for (const char* tool : {"initdb", "pg_ctl", "postgres"})
    if (!fs::exists(fs::path(kBin) / tool))
      throw std::runtime_error(std::string("PostgreSQL's server binaries are missing (") + kBin +
                               "/" + tool +
                               "): install Debian's postgresql (.ci/install-deps) "
                               "to run the journal's PostgreSQL tests");
  if (geteuid() == 0 && !getpwnam("postgres"))
    throw std::runtime_error(
        "running as root, the test cluster needs the user 'postgres' "
        "(Debian's postgresql package creates it)");
  dir_ = (fs::temp_directory_path() / ("penumbra-pg-" + std::to_string(getpid()))).string();
  fs::remove_all(dir_);
  fs::create_directories(dir_);
  if (geteuid() == 0 && std::system(("chown postgres " + dir_).c_str()) != 0)
    throw std::runtime_error("cannot give " + dir_ + " to the user postgres");
  // The tests stop the server, never the machine: no fsync (the journal's commits are still
  // synchronous, to the server's memory).
  if (runAsOwner(std::string(kBin) + "/initdb --no-sync --auth=trust -E UTF8 -U " + kSuperuser +
                 " -D " + dir_ + "/data") != 0)
    throw std::runtime_error("initdb failed in " + dir_);
  start();
}

PostgresCluster::~PostgresCluster() {
  if (running_) runAsOwner(std::string(kBin) + "/pg_ctl -D " + dir_ + "/data -m immediate stop");
  std::error_code error;
  fs::remove_all(dir_, error);
}

void PostgresCluster::start() {
  const std::string options = "-k " + dir_ + " -c listen_addresses= -c fsync=off";
  if (runAsOwner(std::string(kBin) + "/pg_ctl -D " + dir_ + "/data -l " + dir_ +
                 "/log -w -t 30 -o \"" + options + "\" start") != 0)
    throw std::runtime_error("the test PostgreSQL did not start: " + fileText(dir_ + "/log"));
  running_ = true;
}

void PostgresCluster::stop() {
  if (runAsOwner(std::string(kBin) + "/pg_ctl -D " + dir_ + "/data -m fast -w stop") != 0)
    throw std::runtime_error("the test PostgreSQL did not stop: " + fileText(dir_ + "/log"));
  running_ = false;
}

void PostgresCluster::signalAll(int signal) const {
  const pid_t postmaster = std::stoi(fileText(dir_ + "/data/postmaster.pid"));  // its first line
  std::vector<pid_t> children;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    // /proc/PID/stat: "pid (comm) state ppid ..."; comm may hold spaces, not ')'.
    const std::string stat = fileText(entry.path().string() + "/stat");
    const size_t close = stat.rfind(')');
    if (close == std::string::npos) continue;
    std::istringstream rest(stat.substr(close + 1));
    char state = 0;
    pid_t parent = 0;
    if (rest >> state >> parent && parent == postmaster) children.push_back(std::stoi(name));
  }
  // Stopped first, so that it starts no new child; continued last.
  if (signal == SIGSTOP) ::kill(postmaster, signal);
  for (const pid_t child : children) ::kill(child, signal);
  if (signal != SIGSTOP) ::kill(postmaster, signal);
}

void PostgresCluster::pause() { signalAll(SIGSTOP); }
void PostgresCluster::resume() { signalAll(SIGCONT); }

std::string PostgresCluster::uri(const std::string& database) const {
  return "postgresql://" + std::string(kSuperuser) + "@/" + database + "?host=" + dir_;
}

std::string PostgresCluster::freshDatabase() {
  const std::string name = "journal_" + std::to_string(++databases_);
  PGconn* conn = PQconnectdb(uri("postgres").c_str());
  std::string error;
  if (PQstatus(conn) != CONNECTION_OK) {
    error = PQerrorMessage(conn);
  } else {
    PGresult* result = PQexec(conn, ("CREATE DATABASE " + name).c_str());
    if (PQresultStatus(result) != PGRES_COMMAND_OK) error = PQerrorMessage(conn);
    PQclear(result);
  }
  PQfinish(conn);
  if (!error.empty()) throw std::runtime_error("CREATE DATABASE " + name + ": " + error);
  return uri(name);
}

}  // namespace penumbra::server::test
