// A volume object (issue 15): an isosurface of a scalar grid placed in the scene. Render-time
// only: the DM engine never sees it (no faces, no shadows in the mesh; SCENE_FORMAT.md). The
// grid is shared between scene copies (immutable); plain value otherwise; thread-safe to read.
#pragma once

#include <memory>
#include <string>

#include "core/scene/transform.h"
#include "core/volume/scalar_volume.h"

namespace penumbra {

struct VolumeObject {
  std::string id;        // unique among the scene's objects and volumes
  std::string file;      // where the data came from, as resolved by the loader (written back)
  double isovalue = 0;   // the surface is where the trilinear field equals it
  std::string material;  // empty: default material; its albedo shades the surface
  Transform transform;
  std::shared_ptr<const volume::ScalarVolume> data;

  // Voxel i (integer coordinates) to world space: transform ∘ objectFromVoxel.
  Mat4 worldFromVoxel() const {
    Mat4 voxel(1.0);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) voxel[c][r] = data->objectFromVoxel()[c][r];
    return transform.worldFromObject() * voxel;
  }
  bool operator==(const VolumeObject& other) const {
    return id == other.id && file == other.file && isovalue == other.isovalue &&
           material == other.material && transform == other.transform && data == other.data;
  }
};

}  // namespace penumbra
