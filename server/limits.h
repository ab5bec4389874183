// The server's documented limits (docs/API.md "Limits") and URL id syntax. Constants only.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdint>

namespace penumbra::server {

// Documented limits (docs/API.md "Limits").
inline constexpr size_t kMaxBodyBytes = size_t(16) << 20;  // 16 MiB request bodies, else 413
inline constexpr size_t kMaxScenes = 32;                   // served at once, else 429
// cpp-httplib serves a connection on one worker until it closes (keep-alive included): the pool
// (ElasticPool) starts a thread per connection when none is idle, up to kWorkerThreads, so slow
// or idle clients cannot hold every worker (docs/API.md "Load").
inline constexpr int kMaxEventStreams = 64;    // open /events streams, else 429
inline constexpr int kRequestWorkers = 64;     // sizes the edit queues below
inline constexpr int kMinWorkerThreads = 16;   // kept when idle
inline constexpr int kWorkerThreads = 1024;    // connections served at once
inline constexpr int kListenBacklog = 1024;    // connections not yet accepted
inline constexpr int kWorkerIdleSeconds = 30;  // before a thread above the minimum ends
// Edits waiting for their scene's turn: per scene, and over all scenes (so waiting edits
// never hold more than three quarters of the request workers); beyond either, 503 busy.
inline constexpr size_t kMaxQueuedEdits = 16;
// Frames of different clients that queued while a frame applied are applied together, as one
// frame and one version, at most this many (group commit: docs/API.md "Load").
inline constexpr size_t kMaxFramesPerBatch = 16;
inline constexpr int kMaxWaitingEdits = kRequestWorkers * 3 / 4;
// Nice steps between the request threads and the threads applying edits (`serve --edit-nice`).
// 0: in the 10-minute load of README "Load", one edit thread per core already brought GET p99
// from 65 to 27 ms; 5 steps gave 22 ms but 18% fewer edits/s and edit p99 806 instead of 621 ms.
inline constexpr int kEditNiceness = 0;
// Nice steps between the light edit workers and the heavy lane (frames relighting a whole scene,
// isHeavyFrame): at 10 a heavy thread weighs about a tenth of a normal one, so another client's
// drags and reads take a core from it at once (docs/BENCHMARKS.md "A flood from one client").
inline constexpr int kHeavyEditNiceness = 10;
// Images drawn on the request thread with every core: at most this many pixels × samples, and
// no GI (a page's first passes). Larger ones go to the costly images' lane: this many threads
// (more wait in order), each drawing one image on its own (they share the cores, so a short
// image is not stuck behind a GI one), this many nice steps below the request threads.
inline constexpr uint64_t kQuickImageWork = uint64_t(1) << 20;
inline constexpr int kCostlyImageThreads = 8;
inline constexpr int kCostlyImageNiceness = 10;
// A journal snapshot every this many versions of a scene (serve --snapshot-every): a restart
// replays at most this many frames after a build (docs/SERVER.md "Snapshots").
inline constexpr uint64_t kSnapshotEvery = 200;
// How often freed heap memory is given back to the system while requests come (malloc_trim),
// and the malloc arenas `penumbra serve` allows (glibc's default is 8 per core).
inline constexpr std::chrono::milliseconds kTrimInterval{1000};
inline constexpr int kMallocArenas = 2;
// Versions back that mesh deltas name removed parts for; an older `since` gets the whole mesh.
inline constexpr uint64_t kSinceWindow = 256;
inline constexpr int kMaxImageSide = 4096;  // image width/height in [1, 4096]
// Microfacet paths per pixel an image may ask for (`samples`), and the work one image may take:
// samples × width × height at most this (a 4096² image at 1 sample, 1024² at 16).
inline constexpr uint64_t kMaxImageSamples = 256;
inline constexpr uint64_t kMaxImageSampleBudget = uint64_t(1) << 24;
// A render's `seq` (its number among its page's): at most 2^53, the integers a page's JavaScript
// counts exactly.
inline constexpr uint64_t kMaxRenderSeq = uint64_t(1) << 53;
// Working memory of the images rendered at once, each estimated before it starts from its
// pixels (peak RSS on cubes15 at 2048² and 4096²: 23 bytes a pixel, 101 with sensor GI, the
// sensor size and bounces adding little): past it 503 busy; an image that alone needs more is
// refused (400). `serve --image-memory-mib`.
inline constexpr uint64_t kImageMemoryBytes = uint64_t(512) << 20;
inline constexpr uint64_t kImageBytesPerPixel = 24;
inline constexpr uint64_t kGiImageBytesPerPixel = 104;
// Sensor GI on images (`gi=sensors`): sensor maps up to 64², bounces up to 4, and
// width × height × sensor_size² at most 2^27 (a 512 × 256 image with 32² sensors).
inline constexpr uint64_t kMaxGiSensorSize = 64;
inline constexpr uint64_t kMaxGiBounces = 4;
inline constexpr uint64_t kMaxGiRayBudget = uint64_t(1) << 27;
// Indirect light baked on the mesh (`mesh?indirect=1`): sensors of 8² texels at every vertex by
// default, vertices × sensor_size² × bounces at most 2^27 (the 150-cube scene's 62 799 vertices at
// 8²: 2^22), and the bakes of the newest 2 (version, settings) kept per scene.
inline constexpr int kDefaultIndirectSensorSize = 8;
inline constexpr uint64_t kMaxIndirectRayBudget = uint64_t(1) << 27;
inline constexpr size_t kIndirectCacheEntries = 2;
inline constexpr uint64_t kDefaultImageSamples = 16;
// A frame's estimated light work (server/frame_cost.h: light changes × lights × faces + faces
// added × lights) at most this, else 422 frame_too_costly (`serve --max-frame-work`).
inline constexpr uint64_t kMaxFrameWork = uint64_t(1) << 17;
// How long DELETE of a render ticket waits for the render to stop before it answers.
inline constexpr std::chrono::seconds kRenderCancelWait{5};  // the CLI's MicrofacetSettings
// Scene ids in URLs: letters, digits, '_', '-', '.' (so file stems work).
inline constexpr const char* kIdPattern = "([A-Za-z0-9_.-]+)";
inline constexpr size_t kMaxIdLength = 64;

}  // namespace penumbra::server
