// A private, throwaway PostgreSQL 15 cluster for the journal's PostgreSQL tests: initdb in a
// temporary directory, the server listening only on a unix socket in that directory (no TCP
// port), run as the unprivileged user `postgres` when the tests run as root (initdb refuses
// root). Started on first use, one per test binary, stopped and deleted when the binary ends; each
// test takes a fresh database. Missing server binaries are a failure, not a skip. Not thread-safe:
// call from the test's thread.
#pragma once

#include <string>

namespace penumbra::server::test {

class PostgresCluster {
 public:
  // The binary's cluster, started on first call; throws std::runtime_error saying what is missing
  // or what failed (with the server's log).
  static PostgresCluster& shared();

  // Creates an empty database and returns its libpq URI.
  std::string freshDatabase();
  // Stops the server (fast shutdown: connections are cut) and starts it again on the same files.
  void stop();
  void start();
  // Freezes the server without closing anything (SIGSTOP to the postmaster and every process it
  // started, the backends serving open connections included): a database that stops answering.
  // resume() lets it go on (SIGCONT).
  void pause();
  void resume();

  ~PostgresCluster();  // stops the server, deletes the directory

 private:
  PostgresCluster();
  std::string uri(const std::string& database) const;
  void signalAll(int signal) const;  // the postmaster and its children

  std::string dir_;  // the socket and the log; data/ holds the cluster
  int databases_ = 0;
  bool running_ = false;
};

}  // namespace penumbra::server::test
