// `penumbra serve`: the HTTP service on the given scene files until SIGINT/SIGTERM.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <future>
#include <thread>

#include "cli/commands.h"
#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/http_server.h"
#include "server/machine_limits.h"

namespace penumbra::cli {

namespace {

namespace fs = std::filesystem;

// Where the journal lives unless --data says otherwise (relative to the working directory).
constexpr const char* kDefaultDataDir = "penumbra-data";
// How long a stop waits for the requests in flight (exitAfterGrace).
constexpr std::chrono::seconds kStopGrace{4};

// The page: ./web_client, else web_client beside the build directory holding this binary.
std::string defaultStaticDir() {
  if (fs::is_directory("web_client")) return "web_client";
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error && fs::is_directory(exe.parent_path().parent_path() / "web_client"))
    return (exe.parent_path().parent_path() / "web_client").string();
  return "";
}

// A node among several sharing a PostgreSQL journal (docs/SERVER.md "Many nodes").
void nodeOptions(const Args& args, server::ServerOptions& options) {
  for (const char* name : {"node-id", "lease-seconds", "idle-release", "restore"})
    if (args.option(name) && options.journalDatabase.empty())
      throw UsageError(std::string("--") + name +
                       " needs --journal postgresql://... (scene leases live in that database)");
  options.nodeId = args.option("node-id").value_or("");
  options.leaseSeconds = args.doubleOption("lease-seconds", options.leaseSeconds);
  if (!(options.leaseSeconds >= 0.3 && options.leaseSeconds <= 3600))
    throw UsageError("--lease-seconds: give 0.3 to 3600 seconds");
  options.idleReleaseSeconds = args.doubleOption("idle-release", options.idleReleaseSeconds);
  if (!(options.idleReleaseSeconds >= 1))
    throw UsageError("--idle-release: give at least 1 second");
  const std::string restore = args.option("restore").value_or("all");
  if (restore != "all" && restore != "on-request")
    throw UsageError("--restore " + restore + ": give all or on-request");
  options.restoreAtStart = restore == "all";
}

// serve's options, checked: a usage error for what cannot work.
server::ServerOptions serveOptions(const Args& args) {
  args.allowOnly({"host", "port", "static", "grid", "data", "journal", "ephemeral", "token",
                  "allow-origin", "max-scenes", "max-body-mib", "image-memory-mib", "threads",
                  "edit-nice", "mesh-tolerance", "snapshot-every", "node-id", "lease-seconds",
                  "idle-release", "restore", "max-frame-work", "max-connections-per-ip"});
  server::ServerOptions options;
  options.host = args.option("host").value_or("127.0.0.1");
  options.port = args.intOption("port", 8080, 0, 65535);
  options.staticDir = args.option("static").value_or(defaultStaticDir());
  options.engine.overlapGrid = args.intOption("grid", 0, 0, 256);
  options.engine.limits =
      server::limitsForMachine(options.engine.limits, server::physicalMemoryBytes());
  options.maxScenes = size_t(args.intOption("max-scenes", int(server::kMaxScenes), 1, 100000));
  options.maxBodyBytes =
      size_t(args.intOption("max-body-mib", int(server::kMaxBodyBytes >> 20), 1, 4096)) << 20;
  options.imageMemoryBytes =
      uint64_t(
          args.intOption("image-memory-mib", int(server::kImageMemoryBytes >> 20), 16, 1 << 20))
      << 20;
  options.maxFrameWork = uint64_t(
      args.intOption("max-frame-work", int(server::kMaxFrameWork), 1, 1 << 30));
  options.connections.perAddress = size_t(args.intOption(
      "max-connections-per-ip", int(options.connections.perAddress), 1, server::kWorkerThreads));
  const char* envToken = std::getenv("PENUMBRA_TOKEN");
  options.token = args.option("token").value_or(envToken ? envToken : "");
  // --allow-origin A,B: pages of these origins may edit too (e.g. a dev server of the page).
  for (std::string rest = args.option("allow-origin").value_or(""); !rest.empty();) {
    const size_t comma = rest.find(',');
    if (comma) options.allowedOrigins.push_back(rest.substr(0, comma));
    rest = comma == std::string::npos ? "" : rest.substr(comma + 1);
  }
  if (!server::isLoopbackHost(options.host) && options.token.empty())
    throw UsageError("--host " + options.host +
                     " is reachable from other machines: give a token with --token T or the "
                     "PENUMBRA_TOKEN environment variable (mutating requests must then send "
                     "'Authorization: Bearer T'; the page takes ?token=T)");
  if (args.flag("ephemeral") && args.option("data"))
    throw UsageError("--ephemeral and --data exclude each other");
  if (!args.flag("ephemeral")) options.dataDir = args.option("data").value_or(kDefaultDataDir);
  if (const auto journal = args.option("journal")) {
    if (args.flag("ephemeral")) throw UsageError("--ephemeral and --journal exclude each other");
    if (journal->rfind("postgresql://", 0) != 0 && journal->rfind("postgres://", 0) != 0)
      throw UsageError("--journal " + *journal +
                       ": give a PostgreSQL connection URI (postgresql://user@host/database)");
    options.journalDatabase = *journal;
  }
  nodeOptions(args, options);
  options.snapshotEvery =
      uint64_t(args.intOption("snapshot-every", int(server::kSnapshotEvery), 0, 1000000000));
  options.engine.threads = args.intOption("threads", 0, 0, 1024);
  options.engine.meshTolerance = meshToleranceOption(args, kServeMeshTolerance);
  options.editNiceness = args.intOption("edit-nice", server::kEditNiceness, 0, 19);
  if (options.staticDir.empty())
    std::fprintf(
        stderr, "penumbra serve: no web_client/ found (pass --static DIR); serving the API only\n");
  else if (!fs::is_directory(options.staticDir))
    throw UsageError("--static: no directory '" + options.staticDir + "'");
  return options;
}

// The journal's scenes, then the files not already among them; returns the ids served.
std::vector<std::string> serveScenes(server::HttpServer& server, const Args& args,
                                     const server::ServerOptions& options) {
  std::vector<std::string> ids;
  for (const server::RestoredScene& restored : server.restore()) {
    if (restored.served) ids.push_back(restored.id);
    std::fprintf(
        stderr,
        "penumbra serve: restored scene '%s' at version %llu (%s%zu frames%s) in %.2f s%s%s\n",
        restored.id.c_str(), static_cast<unsigned long long>(restored.version),
        restored.snapshot ? ("snapshot at " + std::to_string(*restored.snapshot) + " + ").c_str()
                          : "",
        restored.frames, restored.meshedOnce ? ", meshed once" : "", restored.seconds,
        restored.problem.empty() ? "" : ": ", restored.problem.c_str());
  }
  for (const std::string& path : args.positionals()) {
    const std::string name = fs::path(path).filename().string();
    // The journal wins: a scene already restored under this file's id keeps the user's edits.
    if (!options.dataDir.empty() && server.hasScene(server::sceneIdFromName(name))) {
      std::fprintf(stderr,
                   "penumbra serve: %s: scene '%s' comes from the journal (%s), not the file\n",
                   path.c_str(), server::sceneIdFromName(name).c_str(), options.dataDir.c_str());
      continue;
    }
    Scene scene = protocol::loadSceneFile(path);
    const auto start = std::chrono::steady_clock::now();
    ids.push_back(server.addScene(std::move(scene), name, name));
    std::fprintf(stderr, "penumbra serve: built %s as scene '%s' in %.2f s\n", path.c_str(),
                 ids.back().c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  return ids;
}

// A stop (SIGTERM, Ctrl-C) waits for the requests in flight, but not for ever: builds of new
// scenes, restores of journaled ones, rebuilds and renders are cancelled by the stop at their next progress report, but a
// heavy frame or an import has none. Past the grace the process ends as a
// SIGKILL would, which loses nothing acknowledged: every acknowledged version is committed in the
// journal before its answer, and an unanswered build was never acknowledged (the kill test).
void exitAfterGrace() {
  std::thread([] {
    std::this_thread::sleep_for(kStopGrace);
    std::fprintf(stderr,
                 "penumbra serve: requests still running %lld s after the stop (a build or "
                 "import): ending without them; the journal holds every acknowledged version\n",
                 static_cast<long long>(kStopGrace.count()));
    std::fflush(stderr);
    std::_Exit(0);
  }).detach();
}

}  // namespace

int runServe(const Args& args) {
  const server::ServerOptions options = serveOptions(args);

  // Signals are taken by sigwait below, not by handlers: block them before any
  // thread starts so every worker inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGUSR1);  // the listener ended by itself
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  // One thread takes the signals from the start: a stop while scenes build or restore (minutes
  // for a large journal) ends the process at once, as nothing has been acknowledged yet.
  std::atomic<bool> serving{false};
  std::promise<int> stopSignal;
  std::thread signalWaiter([&signals, &serving, &stopSignal] {
    int signal = 0;
    sigwait(&signals, &signal);
    if (!serving && signal != SIGUSR1) {
      std::fprintf(stderr, "penumbra serve: stopped while starting\n");
      std::_Exit(0);
    }
    stopSignal.set_value(signal);
  });
  // When start-up throws (a scene file that does not load), the waiter is woken and joined.
  struct WakeWaiter {
    std::thread& waiter;
    ~WakeWaiter() {
      if (!waiter.joinable()) return;
      kill(getpid(), SIGUSR1);
      waiter.join();
    }
  } wakeWaiter{signalWaiter};

  server::limitMallocArenas(server::kMallocArenas);  // before the server's threads start
  server::HttpServer server(options);
  // Listening first: while the journal's scenes come back (seconds to minutes), health answers
  // and their requests get 503 restoring instead of a refused connection.
  server.reserveJournalScenes();
  const int port = server.bind();
  std::thread listener([&server] {
    server.listen();
    kill(getpid(), SIGUSR1);
  });
  for (int i = 0; i < 500 && !server.isRunning(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  std::fprintf(stderr, "penumbra serve: listening on port %d; restoring and building scenes\n",
               port);
  const std::vector<std::string> ids = serveScenes(server, args, options);

  // Inside a container the server listens on 0.0.0.0; the user opens localhost.
  const std::string shownHost = options.host == "0.0.0.0" ? "localhost" : options.host;
  const std::string url = "http://" + shownHost + ":" + std::to_string(port) + "/";
  std::printf("penumbra: serving %zu scene%s at %s\n", ids.size(), ids.size() == 1 ? "" : "s",
              url.c_str());
  const std::string tokenQuery = options.token.empty() ? "" : "&token=" + options.token;
  for (const std::string& id : ids)
    std::printf("  open %s?scene=%s%s\n", url.c_str(), id.c_str(), tokenQuery.c_str());
  const std::string keptIn =
      options.journalDatabase.empty()
          ? options.dataDir
          : "the PostgreSQL journal, uploads too (copies in " + options.dataDir + ")";
  std::printf("  (scenes and edits %s)\n", options.dataDir.empty()
                                               ? "are not kept: --ephemeral"
                                               : ("are kept in " + keptIn).c_str());
  std::printf("  (API: %sapi/health; stop with Ctrl-C)\n", url.c_str());
  std::fflush(stdout);

  serving = true;
  const int signal = stopSignal.get_future().get();
  signalWaiter.join();
  if (signal != SIGUSR1) exitAfterGrace();
  server.stop();
  listener.join();
  if (signal != SIGUSR1) std::fprintf(stderr, "penumbra serve: stopped\n");
  return 0;
}

}  // namespace penumbra::cli
