#include <cstdio>

#include "protocol/scene_json.h"
#include "cli/commands.h"

namespace penumbra::cli {

int runInfo(const Args& args) {
  args.allowOnly({});
  const std::string path = args.positional(0, "SCENE");
  const Scene scene = protocol::loadSceneFile(path);

  size_t receiving = 0;
  for (const Face& face : scene.faces()) receiving += scene.receivesLight(face);
  const Bounds bounds = scene.bounds();
  std::printf("scene      %s\n", path.c_str());
  std::printf("objects    %zu\n", scene.objects().size());
  for (const VolumeObject& volume : scene.volumes())
    std::printf("volume     %s: %s, %d x %d x %d %s, isovalue %g (render-time only: not in the DM)\n",
                volume.id.c_str(), volume.file.c_str(), volume.data->size().x, volume.data->size().y,
                volume.data->size().z, volume.data->typeName().c_str(), volume.isovalue);
  std::printf("faces      %zu (%zu receive light)\n", scene.faces().size(), receiving);
  std::printf("materials  %zu\n", scene.materials().size());
  std::printf("bounds     [%g, %g, %g] .. [%g, %g, %g] (diagonal %g m)\n", bounds.min.x,
              bounds.min.y, bounds.min.z, bounds.max.x, bounds.max.y, bounds.max.z,
              bounds.diagonal());
  std::printf("lights     %zu\n", scene.lights().size());
  for (const Light& light : scene.lights()) {
    size_t front = 0, offending = 0, back = 0;
    for (const Face& face : scene.faces()) {
      switch (scene.classify(face, light)) {
        case FaceClass::Front: ++front; break;
        case FaceClass::Offending: ++offending; break;
        case FaceClass::Back: ++back; break;
      }
    }
    std::printf("  %-10s %zu vertices, area %g m², radiance [%g, %g, %g]; faces: %zu front, "
                "%zu offending, %zu back\n",
                light.id.c_str(), light.polygon.size(), light.area(), light.radiance.x,
                light.radiance.y, light.radiance.z, front, offending, back);
  }
  return 0;
}

}  // namespace penumbra::cli
