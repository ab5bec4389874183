#include <chrono>
#include <cstdio>
#include <filesystem>

#include "core/reference/grid_mesh.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"
#include "cli/commands.h"
#include "cli/progress_bar.h"

namespace penumbra::cli {

int runReference(const Args& args) {
  args.allowOnly({"grid", "out"});
  const std::string scenePath = args.positional(0, "SCENE");
  const int grid = args.intOption("grid", 8, 1, 1000);
  const auto out = args.option("out");
  if (!out) throw UsageError("reference needs --out MESH");
  const Scene scene = protocol::loadSceneFile(scenePath);

  const auto start = std::chrono::steady_clock::now();
  ProgressBar bar("reference");
  const Mesh mesh = referenceGridMesh(scene, grid, [&](size_t done, size_t total) { bar.update(done, total); });
  bar.finish();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  protocol::saveMeshFile(scene, mesh, std::filesystem::path(scenePath).filename().string(), *out);
  std::printf("wrote %s: %zu receivers, %zu vertices, %zu triangles (%.2f s, %.1f us per vertex)\n",
              out->c_str(), mesh.receivers.size(), mesh.vertexCount(), mesh.triangleCount(), seconds,
              mesh.vertexCount() ? 1e6 * seconds / double(mesh.vertexCount()) : 0.0);
  return 0;
}

}  // namespace penumbra::cli
