// NRRD volumes (teem.sourceforge.net/nrrd/format.html) through Teem, the format's reference
// implementation: a reader for scene volume objects and a writer for tests and generators.
// Free functions; thread-safe (Teem's global error and verbosity state is behind a mutex).
#pragma once

#include <memory>
#include <stdexcept>
#include <string>

#include "core/geom/vec.h"
#include "core/volume/dense_grid.h"
#include "core/volume/scalar_volume.h"

namespace penumbra::protocol {

// A file the reader refuses; what() is the problem in words, without the path.
class NrrdError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Per-volume limits, checked on the header before any data is read: a larger volume is a
// ResourceLimitError ("volume_voxels", "volume_side"), not an allocation failure.
struct NrrdLimits {
  size_t maxVoxels = size_t(512) * 512 * 512;  // the largest test size
  size_t maxSide = 8192;
};

// Reads a 3D NRRD: type uchar, ushort or float; encoding raw or gzip; data in the file (a
// detached header's "data file" is refused: a scene must not read files it does not name);
// every side ≥ 2; float voxels finite. Voxel i sits at objectFromVoxel·i, whose columns are
// the `space directions` when given, else diag(`spacings`) (1 where absent); `space origin`
// is ignored (the object's transform places the volume). Throws NrrdError or
// ResourceLimitError; the octree is built from the data (lossless).
std::shared_ptr<const volume::ScalarVolume> readNrrdVolume(const std::string& path,
                                                           const NrrdLimits& limits = {});

// Writes a grid as NRRD0004 with `spacings` (gzip-encoded when gzip, else raw). Throws
// std::runtime_error when the file cannot be written. T: uint8_t, uint16_t or float.
template <class T>
void writeNrrdVolume(const std::string& path, const volume::DenseGrid<T>& grid, const Vec3& spacing,
                     bool gzip = true);

}  // namespace penumbra::protocol
