// The server's documented limits (docs/API.md "Limits") and URL id syntax. Constants only.
#pragma once

#include <cstddef>

namespace penumbra::server {

// Documented limits (docs/API.md "Limits").
inline constexpr size_t kMaxBodyBytes = size_t(16) << 20;  // 16 MiB request bodies, else 413
inline constexpr size_t kMaxScenes = 32;                   // served at once, else 429
inline constexpr int kMaxEventStreams = 8;                 // open /events streams, else 429
inline constexpr int kRequestWorkers = 16;                 // workers left for ordinary requests
inline constexpr int kWorkerThreads = kMaxEventStreams + kRequestWorkers;
inline constexpr int kMaxImageSide = 4096;  // image width/height in [1, 4096]
// Scene ids in URLs: letters, digits, '_', '-', '.' (so file stems work).
inline constexpr const char* kIdPattern = "([A-Za-z0-9_.-]+)";
inline constexpr size_t kMaxIdLength = 64;

}  // namespace penumbra::server
