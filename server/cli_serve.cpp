// `penumbra serve`: the HTTP service on the given scene files until SIGINT/SIGTERM.
#include <pthread.h>
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "protocol/scene_json.h"
#include "server/api_errors.h"
#include "server/commands.h"
#include "server/http_server.h"

namespace penumbra::cli {

namespace {

namespace fs = std::filesystem;

// The page: ./web_client, else web_client beside the build directory holding this binary.
std::string defaultStaticDir() {
  if (fs::is_directory("web_client")) return "web_client";
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (!error && fs::is_directory(exe.parent_path().parent_path() / "web_client"))
    return (exe.parent_path().parent_path() / "web_client").string();
  return "";
}

}  // namespace

int runServe(const Args& args) {
  args.allowOnly({"host", "port", "static", "grid", "threads"});
  server::ServerOptions options;
  options.host = args.option("host").value_or("127.0.0.1");
  options.port = args.intOption("port", 8080, 0, 65535);
  options.staticDir = args.option("static").value_or(defaultStaticDir());
  options.engine.overlapGrid = args.intOption("grid", 0, 0, 256);
  options.engine.threads = args.intOption("threads", 0, 0, 1024);
  if (options.staticDir.empty())
    std::fprintf(
        stderr, "penumbra serve: no web_client/ found (pass --static DIR); serving the API only\n");
  else if (!fs::is_directory(options.staticDir))
    throw UsageError("--static: no directory '" + options.staticDir + "'");

  // Signals are taken by sigwait below, not by handlers: block them before any
  // thread starts so every worker inherits the mask.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  sigaddset(&signals, SIGUSR1);  // the listener ended by itself
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);

  server::HttpServer server(options);
  std::vector<std::string> ids;
  for (const std::string& path : args.positionals()) {
    Scene scene = protocol::loadSceneFile(path);
    const auto start = std::chrono::steady_clock::now();
    const std::string name = fs::path(path).filename().string();
    ids.push_back(server.addScene(std::move(scene), name, name));
    std::fprintf(stderr, "penumbra serve: built %s as scene '%s' in %.2f s\n", path.c_str(),
                 ids.back().c_str(),
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
  const int port = server.bind();
  std::thread listener([&server] {
    server.listen();
    kill(getpid(), SIGUSR1);
  });
  for (int i = 0; i < 500 && !server.isRunning(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));

  // Inside a container the server listens on 0.0.0.0; the user opens localhost.
  const std::string shownHost = options.host == "0.0.0.0" ? "localhost" : options.host;
  const std::string url = "http://" + shownHost + ":" + std::to_string(port) + "/";
  std::printf("penumbra: serving %zu scene%s at %s\n", ids.size(), ids.size() == 1 ? "" : "s",
              url.c_str());
  for (const std::string& id : ids) std::printf("  open %s?scene=%s\n", url.c_str(), id.c_str());
  std::printf("  (API: %sapi/health; stop with Ctrl-C)\n", url.c_str());
  std::fflush(stdout);

  int signal = 0;
  sigwait(&signals, &signal);
  server.stop();
  listener.join();
  if (signal != SIGUSR1) std::fprintf(stderr, "penumbra serve: stopped\n");
  return 0;
}

}  // namespace penumbra::cli
