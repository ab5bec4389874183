#include <cstdio>

#include "protocol/scene_json.h"
#include "cli/commands.h"

namespace penumbra::cli {

int runValidate(const Args& args) {
  args.allowOnly({});
  const std::string path = args.positional(0, "SCENE");
  const Scene scene = protocol::loadSceneFile(path);
  std::printf("%s: valid scene (%zu objects, %zu faces, %zu lights", path.c_str(), scene.objects().size(),
              scene.faces().size(), scene.lights().size());
  // Volumes are not DM objects (SCENE_FORMAT.md): counted apart.
  if (!scene.volumes().empty()) std::printf(", %zu volumes", scene.volumes().size());
  std::printf(")\n");
  return 0;
}

}  // namespace penumbra::cli
