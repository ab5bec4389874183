#include "core/engine/cube_grid.h"

#include "core/overlap/overlap_cube.h"
#include "core/shadow/object_shadow.h"

namespace penumbra {

int overlapGridFor(const Scene& scene, size_t light, bool wholeObjects) {
  size_t counted = scene.faces().size();
  if (wholeObjects)
    for (size_t i = 0; i < scene.objects().size(); ++i) {
      const uint32_t handle = scene.handleOf(i);
      const size_t faces = scene.facesOfObject(handle).size();
      if (faces > kMeshFacesCounted && castsWholeOnItself(scene, light, handle)) counted -= faces - kMeshFacesCounted;
    }
  return OverlapCube::gridForFaceCount(counted);
}

}  // namespace penumbra
