// The HTTP service (docs/API.md): REST API, server-sent events and the static page on
// cpp-httplib, one engine session per scene. Methods are thread-safe; handlers run on its pool.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <map>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/engine/engine.h"
#include "server/build_job.h"
#include "server/connection_server.h"
#include "server/edit_workers.h"
#include "server/limits.h"
#include "server/memory_trim.h"
#include "server/render_jobs.h"
#include "server/restore_job.h"
#include "server/scene_journal.h"
#include "server/scene_leases.h"
#include "server/scene_session.h"
#include "server/static_files.h"
#include "server/work_budget.h"
#include "server/work_lane.h"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace penumbra::server {

struct ServerOptions {
  std::string host = "127.0.0.1";
  int port = 8080;        // 0: any free port (see HttpServer::port)
  std::string staticDir;  // served at "/" (empty: no page); node_modules beside or inside it at
                          // /node_modules
  EngineSettings engine;
  // gzip of binary mesh responses for clients that accept it (docs/API.md "Binary"):
  // Auto compresses only for non-loopback clients (on loopback, compressing costs more
  // time than sending the bytes).
  enum class MeshCompression { Auto, Always, Never };
  MeshCompression meshCompression = MeshCompression::Auto;
  // The journal's directory (README "Durability"); empty: ephemeral, nothing survives a restart.
  std::string dataDir;
  // Not empty: the journal is kept in this PostgreSQL database (a libpq connection URI,
  // postgresql://…) instead of dataDir's SQLite file; uploaded files stay in dataDir.
  std::string journalDatabase;
  // Required (Authorization: Bearer TOKEN) on every POST/PUT/PATCH/DELETE when not empty; a
  // host other than loopback is refused without one.
  std::string token;
  // Origins ("http://host:port") whose pages may send mutating requests besides the server's own
  // (same origin: Origin = http:// + Host); any other Origin is refused with 403. On a loopback
  // address a Host naming anything but loopback is refused too (DNS rebinding), unless it is the
  // host of one of these.
  std::vector<std::string> allowedOrigins;
  size_t maxScenes = kMaxScenes;                  // served at once, else 429
  size_t maxBodyBytes = kMaxBodyBytes;            // request bodies, else 413
  uint64_t imageMemoryBytes = kImageMemoryBytes;  // images rendering at once (WorkBudget)
  // Edit batches apply on one thread per core, this many nice steps below the request
  // threads, heavy frames on one more thread kHeavyEditNiceness steps further below
  // (server/edit_workers.h).
  int editNiceness = kEditNiceness;
  // Every this many versions a journaled scene is snapshotted (docs/SERVER.md "Snapshots"), so
  // a restart replays at most that many frames; 0: never.
  uint64_t snapshotEvery = kSnapshotEvery;
  // With a PostgreSQL journal, nodes sharing it each serve a scene only while they hold its
  // lease (scene_leases.h; docs/SERVER.md "Many nodes"). This node's name in the leases (empty:
  // hostname:port).
  std::string nodeId;
  double leaseSeconds = 3;  // how long a lease outlives its last renewal (renewed every third)
  // A scene nobody asked for in this long (and with no event stream open) is given back.
  double idleReleaseSeconds = 600;
  // Start-up restores every journaled scene whose lease is free (one node, as with SQLite);
  // false: a scene comes back when first asked for (a node among several).
  bool restoreAtStart = true;
  // Connections per client address, and how fast a request's head and body must arrive
  // (server/connection_server.h; `serve --max-connections-per-ip`).
  ConnectionLimits connections;
  // A frame whose estimated work (server/frame_cost.h) is past this is refused with 422.
  uint64_t maxFrameWork = kMaxFrameWork;
};

// The id a scene named `name` asks for ("cubes15.scene.json" → "cubes15").
std::string sceneIdFromName(const std::string& name);
// 127.0.0.0/8, ::1 and "localhost".
bool isLoopbackHost(const std::string& host);

// A scene restore() brought back from the journal.
struct RestoredScene {
  std::string id;
  uint64_t version = 0;  // the last acknowledged version it is back at
  size_t frames = 0;     // frames replayed
  bool meshedOnce =
      false;           // replayed through the engine alone and meshed once (part changes journaled)
  double seconds = 0;  // build + replay
  bool served = true;  // false: the scene no longer builds (kept in the journal, not served)
  // Set when restore stopped before the journal's last frame (a frame that fails its checksum or
  // no longer applies): the version it is served at. The later frames stay in the journal.
  std::optional<uint64_t> stalledAt;
  std::string problem;  // not empty: why not served, or where and why it stalled
  std::optional<uint64_t> snapshot;  // the journal snapshot it started from (`frames` after it)
  // Not empty: damage passed over (a snapshot that fails its checksum or does not load, a frame
  // a snapshot covers), and what the restore did instead; the scene itself came back whole.
  std::string snapshotProblem;
};

// A scene restore stopped short of its journal: served read-only at `version` (edits answer 409,
// so no new version overwrites a kept frame) until an operator repairs the journal.
struct SceneStall {
  uint64_t version = 0;
  std::string problem;
};

// A problem restore met, for /api/health: the scene, where it stalled (if served), and why.
struct JournalProblem {
  std::string id;
  std::optional<uint64_t> stalledAt;
  std::string problem;
};

class HttpServer {
 public:
  explicit HttpServer(ServerOptions options);
  ~HttpServer();  // stops and waits for the workers
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Builds and serves a scene as POST /api/scenes would; `preferredId` is used when
  // free and well-formed. Returns the id. Throws ApiError (e.g. too many scenes; 409
  // build_cancelled when cancelBuild or stop() ended it).
  std::string addScene(Scene scene, const std::string& name, const std::string& preferredId = "");
  // addScene in two steps (scene_builds.cpp), so a request can report its import too: reserve
  // the id (listed as building from then on; throws ApiError 429 when full), then build the
  // scene under that job. buildScene frees the reservation when it throws; a caller that gives
  // up before calling it calls abandonBuild.
  std::shared_ptr<BuildJob> reserveBuild(const std::string& name, const std::string& preferredId,
                                         const std::string& ticket = "");
  std::string buildScene(const std::shared_ptr<BuildJob>& job, Scene scene,
                         const std::string& name);
  void abandonBuild(BuildJob& job);
  // Cancels the build of scene `id` and waits until its request gave the id up (or the build
  // finished first: then the scene is served). False when `id` is not building.
  bool cancelBuild(const std::string& id);
  // The scenes being built now, as BuildJob::toJson.
  std::vector<nlohmann::json> buildsJson() const;
  // Whether scene `id` is served (built, not reserved or restoring).
  bool servesScene(const std::string& id) const;
  // The job building scene `id`; null when it is not building.
  std::shared_ptr<BuildJob> findBuild(const std::string& id) const;
  // Cancels the restore of scene `id` for its DELETE (restore_job.h) and waits until the restoring
  // thread ended it: removed from the journal, or served (it finished first), or the removal
  // failed (Ended::problem). Nullopt when `id` is not restoring. Throws ApiError 503 when the
  // restore does not stop within the wait.
  std::optional<RestoreJob::Ended> cancelRestore(const std::string& id);

  // Reads the journal and reserves its scenes' ids: until restore() brings one back, requests
  // for it get 503 restoring. Call before listening (restore() calls it when nobody did).
  void reserveJournalScenes();
  // Rebuilds every journaled scene and replays its frames (no-op when ephemeral). Call once,
  // before addScene, so that journaled scenes keep their ids; the server may already listen.
  std::vector<RestoredScene> restore();
  bool hasScene(const std::string& id) const;
  // The stall restore left on a served scene, if any (SceneStall).
  std::optional<SceneStall> stallOf(const SceneSession& session) const;

  // Binds the listening socket; returns the port. Throws std::runtime_error.
  int bind();
  // Serves until stop() (blocks; run it on a thread of its own). Call after bind().
  void listen();
  // Ends event streams, closes the socket; listen() then returns once the
  // workers have finished their requests.
  void stop();
  bool isRunning() const;
  int port() const { return port_; }
  const ServerOptions& options() const { return options_; }
  // The threads applying edit batches (a test may hold their heavy lane with work of its own).
  EditWorkers& editWorkers() { return editWorkers_; }
  // Connections from `address` holding a slot of its cap now (ConnectionServer).
  size_t connectionsFrom(const std::string& address) const;

 private:
  // One per resource, each in its own file (scene_routes.cpp, edit_routes.cpp, ...).
  void registerRoutes();
  void registerSceneRoutes();
  void registerEditRoutes();
  void registerMeshRoutes();
  void registerImageRoutes();
  void registerEventRoutes();
  void registerVolumeRoutes();
  void registerRenameRoutes();
  void registerBodyFallbacks();
  std::optional<WorkBudget::Share> takeImageMemory(uint64_t pixels, bool gi);
  // The render `ticket` of scene `sceneId`, running or recently ended; else 404.
  std::shared_ptr<RenderJob> findRender(const std::string& sceneId, const std::string& ticket) const;
  void registerStaticFiles();
  // Answers (and returns true) when the request may not go on: no token on a mutating
  // request, a static path leading out of its root (access_control.cpp).
  bool refuseAccess(const httplib::Request& req, httplib::Response& res) const;
  // A Host other than loopback on a loopback server, or a mutating request whose Origin is
  // neither this server's nor allowed: 403 forbidden_origin (access_control.cpp).
  bool refuseForeignOrigin(const httplib::Request& req, httplib::Response& res) const;
  // The journal's key of a served scene; throws 503 owned_elsewhere when this node dropped it
  // since the request found it, 404 when it was deleted.
  int64_t journalKeyOf(const SceneSession& session) const;
  // Journal writes (no-ops when ephemeral); throw ApiError 503 when the journal fails.
  // `next`: the version the frame made (its number, and its part changes for a fast restore).
  void journalFrame(const SceneSession& session, const SceneSnapshot& next,
                    const std::string& frame);
  // Edit frames (edit_routes.cpp): a batch of queued frames applied as one frame when they
  // touch different objects, else (or when that fails) one by one; answers in the tickets.
  void applyFrameBatch(SceneSession& session, const std::vector<EditScheduler::Ticket*>& batch);
  void applyFrameAlone(SceneSession& session, EditScheduler::Ticket& ticket);
  // After `version` was published: at every snapshotEvery-th version, the session is rebased
  // and the journal records the snapshot (journal_snapshots.cpp). A failure only costs the
  // snapshot (said on stderr): the next one is taken snapshotEvery versions later.
  void snapshotIfDue(SceneSession& session, uint64_t version);
  // Queues a checked frame for its scene (round-robin, bounded) and answers `res` with what
  // applying it did; `journaled` is the frame's JSON as the journal keeps it.
  void submitFrame(SceneSession& session, Frame frame, const std::string& journaled,
                   const httplib::Request& req, httplib::Response& res);
  // Where uploaded volume files are kept (volume_routes.cpp): the data directory's
  // `volumes/`, or a temporary folder when ephemeral; created on first use.
  std::string volumeUploadDir();
  // Deletes this node's files of the volumes uploaded to scene `sceneId` (after the scene left
  // the journal, or this node: the journal keeps them).
  void removeUploadsOf(const std::string& sceneId);
  // An upload kept where every restore finds it (volume_routes.cpp): with a journal, stored in it
  // (SceneJournal::addVolume: committed, fenced, this node's copy at `path`); else a file in the
  // upload folder. Throws ApiError 503 when it cannot be kept (owned_elsewhere: the lease lost).
  struct KeptUpload {
    std::string path;            // this node's file, which the engine reads
    std::optional<int64_t> key;  // the scene's journal key, when journaled
    std::string name;            // volumes/FILE, as the journal names it
  };
  KeptUpload keepUpload(SceneSession& session, const std::string& bytes);
  void discardUpload(const KeptUpload& upload);  // its frame was refused; never throws
  void journalRemove(const SceneSession& session);
  // A frame's JSON as the journal keeps it: the volume files it adds under the data directory
  // written relative to it (so the directory may be moved), other files as resolved.
  std::string journaledFrameText(const Frame& frame) const;
  // 409 scene_stalled when restore left the scene stalled (SceneStall).
  void refuseIfStalled(const SceneSession& session) const;
  // 503 journal_failed when commits would not be durable (the data directory gone, replaced or
  // unwritable): checked before work that writes files, such as a volume upload.
  void refuseIfNotDurable() const;
  // /api/health's "journal" member: path, integrity, durability, stalled scenes
  // (journal_write_restore.cpp).
  nlohmann::json journalHealthJson() const;
  // The served scene `id`; with leases, one not served here is taken over (takeOver). Throws
  // ApiError 404 (no such scene), 503 + Retry-After (restoring, building, owned elsewhere).
  std::shared_ptr<SceneSession> findScene(const std::string& id);
  // Scene ownership among nodes (scene_ownership.cpp; null leases_: SQLite or ephemeral).
  void startLeases();
  void stopLeases();  // every lease given back (SIGTERM: another node takes the scenes at once)
  // Takes the lease of scene `id` (reserved as restoring by the caller) and restores it from
  // the journal; frees the reservation and throws ApiError when it cannot.
  std::shared_ptr<SceneSession> takeOver(const std::string& id);
  // Whether a new scene may take id `id` here: its lease taken, no journaled scene has it.
  bool claimNewId(const std::string& id);
  // The scene stops being served here (its lease lost, handed over, idle): its streams end.
  // Returns its lease token, if it had one.
  std::optional<int64_t> dropScene(const std::string& id, const std::string& why);
  // Start-up with every scene restored: keeps the scenes whose lease this node took.
  void takeLeasesOf(std::vector<SceneJournal::StoredScene>& scenes);
  void keepLeases();  // the renewal thread
  void renewLeasesOnce();
  // Brings one journaled scene back (journal_write_restore.cpp), its problems noted for
  // /api/health; null when it no longer builds. `job`'s cancel ends it with BuildCancelled (at
  // the engine's next report, or between frames), nothing noted.
  std::shared_ptr<SceneSession> restoreStored(const SceneJournal::StoredScene& stored,
                                              RestoredScene& report, RestoreJob& job);
  // The restoring thread after a cancelled restore of scene `id` (journal key `key`, if read):
  // when a DELETE cancelled it, the scene leaves the journal and its uploads' copies go; a stop's
  // cancel changes nothing. Returns what the job's waiter is told.
  RestoreJob::Ended dropCancelledRestore(const std::string& id, std::optional<int64_t> key,
                                         const RestoreJob& job);
  std::string freshId(const std::string& preferred);  // call with scenesMutex_ held

  ServerOptions options_;
  MemoryTrimmer trimmer_{kTrimInterval};  // gives freed memory back after requests (outlives http_)
  WorkBudget imageBudget_;   // working memory of the images rendering now (image_routes)
  RenderJobs renders_;       // the images rendering now and just ended, by ticket
  EditWorkers editWorkers_;  // apply edit batches: one per core, and the heavy lane (outlives http_)
  WorkLane costlyImages_;    // draw GI and large images, below edits (outlives http_)
  std::unique_ptr<httplib::Server> http_;
  int port_ = 0;
  std::atomic<bool> stopping_{false};
  int listenSocket_ = -1;  // the bound socket (set by httplib's socket-options callback)
  std::atomic<int> openStreams_{0};
  std::atomic<int> waitingEdits_{0};  // edits waiting for their scene's turn, all scenes
  mutable std::mutex scenesMutex_;    // guards scenes_, nextId_, journalKeys_
  std::map<std::string, std::shared_ptr<SceneSession>> scenes_;
  std::map<std::string, std::shared_ptr<BuildJob>> builds_;  // ids reserved in scenes_, building
  std::unique_ptr<SceneJournal> journal_;                                 // null: ephemeral
  std::map<const SceneSession*, int64_t> journalKeys_;                    // guarded by scenesMutex_
  std::map<const SceneSession*, SceneStall> stalls_;                      // guarded by scenesMutex_
  std::optional<std::vector<SceneJournal::StoredScene>> pendingRestore_;  // reserved, not restored
  // Journal scenes not back yet (503 restoring), each with its cancellable job; scenesMutex_.
  std::map<std::string, std::shared_ptr<RestoreJob>> restoring_;
  std::vector<JournalProblem> journalProblems_;                   // guarded by scenesMutex_
  // Snapshot damage restore passed over (RestoredScene::snapshotProblem): id → what; scenesMutex_
  std::vector<std::pair<std::string, std::string>> snapshotProblems_;
  std::vector<std::pair<std::string, std::string>> staticRoots_;  // URL prefix → canonical dir
  StaticFiles staticFiles_;  // the page, served from those roots
  size_t nextId_ = 1;
  std::unique_ptr<SceneLeases> leases_;
  std::map<std::string, int64_t> leaseTokens_;  // scene id → its lease's token; scenesMutex_
  std::map<std::string, std::chrono::steady_clock::time_point> lastUse_;  // scenesMutex_
  std::mutex leaseStopMutex_;
  std::condition_variable leaseStop_;
  bool leasesStopping_ = false;  // guarded by leaseStopMutex_
  std::thread leaseKeeper_;
  std::chrono::steady_clock::time_point leasesRenewedAt_ = std::chrono::steady_clock::now();
  std::mutex uploadDirMutex_;
  std::string uploadDir_;  // volumeUploadDir(), once made
};

}  // namespace penumbra::server
