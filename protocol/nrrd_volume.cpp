#include "protocol/nrrd_volume.h"

#include <teem/nrrd.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>

#include "core/geom/resource_limit.h"

namespace penumbra::protocol {

namespace {

// Teem keeps its error messages (biff) and verbosity in globals: one caller at a time.
std::mutex& teemMutex() {
  static std::mutex mutex;
  return mutex;
}

// Teem's message is a stack of "[nrrd] function: text" lines, outermost first; the innermost
// names the actual problem.
std::string teemProblem() {
  char* raw = biffGetDone(NRRD);
  std::string all = raw ? raw : "";
  std::free(raw);
  std::string last;
  size_t start = 0;
  while (start < all.size()) {
    size_t end = all.find('\n', start);
    if (end == std::string::npos) end = all.size();
    std::string line = all.substr(start, end - start);
    if (const size_t colon = line.find(": ");
        line.rfind("[nrrd]", 0) == 0 && colon != std::string::npos)
      line = line.substr(colon + 2);
    if (!line.empty()) last = line;
    start = end + 1;
  }
  return last.empty() ? "unreadable NRRD" : last;
}

// Owns a Nrrd and its reading state (Teem's C API).
struct TeemRead {
  Nrrd* nrrd = nrrdNew();
  NrrdIoState* io = nrrdIoStateNew();
  ~TeemRead() {
    nrrdIoStateNix(io);
    nrrdNuke(nrrd);
  }
  // Teem's words, after ours: the header pass fails on the header, the data pass on the data.
  void load(const std::string& path, bool headerOnly) {
    io->skipData = headerOnly ? AIR_TRUE : AIR_FALSE;
    if (nrrdLoad(nrrd, path.c_str(), io))
      throw NrrdError(std::string(headerOnly ? "bad NRRD header" : "data truncated or corrupt") +
                      " (Teem: " + teemProblem() + ")");
  }
};

std::string sideText(const Nrrd* nrrd) {
  return std::to_string(nrrd->axis[0].size) + " × " + std::to_string(nrrd->axis[1].size) + " × " +
         std::to_string(nrrd->axis[2].size);
}

// The header's checks, before any data is read.
void checkHeader(const TeemRead& read, const NrrdLimits& limits) {
  const Nrrd* nrrd = read.nrrd;
  if (read.io->format != nrrdFormatNRRD)
    throw NrrdError("not a NRRD file (Teem read it as another format)");
  if (read.io->dataFNFormat || read.io->dataFNArr->len > 0)
    throw NrrdError(
        "detached data ('data file') is not supported: keep the data in the .nrrd file");
  if (read.io->encoding != nrrdEncodingRaw && read.io->encoding != nrrdEncodingGzip)
    throw NrrdError(std::string("encoding '") + read.io->encoding->name +
                    "' is not supported (raw, gzip)");
  if (nrrd->dim != 3) throw NrrdError("dimension is " + std::to_string(nrrd->dim) + ", not 3");
  if (nrrd->type != nrrdTypeUChar && nrrd->type != nrrdTypeUShort && nrrd->type != nrrdTypeFloat)
    throw NrrdError(std::string("type '") + airEnumStr(nrrdType, nrrd->type) +
                    "' is not supported (uchar, ushort, float)");
  double voxels = 1;
  for (int a = 0; a < 3; ++a) {
    const size_t side = nrrd->axis[a].size;
    if (side > limits.maxSide) throw ResourceLimitError("volume_side", side, limits.maxSide);
    if (side < 2)
      throw NrrdError("sizes " + sideText(nrrd) + ": every side needs at least 2 voxels");
    voxels *= double(side);
  }
  if (voxels > double(limits.maxVoxels))
    throw ResourceLimitError("volume_voxels", size_t(std::min(voxels, 1e19)), limits.maxVoxels);
}

// objectFromVoxel: space directions as columns, else the spacings (1 where absent).
Mat3 voxelMap(const Nrrd* nrrd) {
  Mat3 map(1.0);
  for (int a = 0; a < 3; ++a) {
    const NrrdAxisInfo& axis = nrrd->axis[a];
    if (nrrd->spaceDim > 0) {
      if (nrrd->spaceDim != 3)
        throw NrrdError("space dimension is " + std::to_string(nrrd->spaceDim) + ", not 3");
      for (int r = 0; r < 3; ++r) map[a][r] = axis.spaceDirection[r];
    } else if (!std::isnan(axis.spacing)) {
      map[a][a] = axis.spacing;
    }
    for (int r = 0; r < 3; ++r)
      if (!std::isfinite(map[a][r]))
        throw NrrdError("axis " + std::to_string(a) + ": spacing or space direction is not finite");
  }
  const double det = glm::determinant(map);
  if (!(std::abs(det) > 0) || !std::isfinite(det))
    throw NrrdError("spacings / space directions are degenerate (zero volume per voxel)");
  return map;
}

template <class T>
std::shared_ptr<const volume::ScalarVolume> fromData(const Nrrd* nrrd, const Mat3& map) {
  volume::DenseGrid<T> grid(
      glm::ivec3(int(nrrd->axis[0].size), int(nrrd->axis[1].size), int(nrrd->axis[2].size)));
  std::memcpy(grid.values.data(), nrrd->data, grid.bytes());
  if constexpr (std::is_floating_point_v<T>) {
    for (size_t k = 0; k < grid.values.size(); ++k)
      if (!std::isfinite(grid.values[k]))
        throw NrrdError("voxel " + std::to_string(k) + " is not a finite number");
  }
  return std::make_shared<const volume::ScalarVolume>(grid, map);
}

}  // namespace

std::shared_ptr<const volume::ScalarVolume> readNrrdVolume(const std::string& path,
                                                           const NrrdLimits& limits) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) throw NrrdError("no such file");
  Mat3 map;
  TeemRead read;
  {
    std::lock_guard lock(teemMutex());
    nrrdStateVerboseIO = 0;  // Teem would print warnings (trailing bytes) to stderr
    {
      TeemRead header;  // a reading state serves one read
      header.load(path, true);
      checkHeader(header, limits);
      map = voxelMap(header.nrrd);
    }
    read.load(path, false);
    checkHeader(read, limits);  // the same file, unless it changed in between
  }
  switch (read.nrrd->type) {
    case nrrdTypeUChar:
      return fromData<uint8_t>(read.nrrd, map);
    case nrrdTypeUShort:
      return fromData<uint16_t>(read.nrrd, map);
    default:
      return fromData<float>(read.nrrd, map);
  }
}

template <class T>
void writeNrrdVolume(const std::string& path, const volume::DenseGrid<T>& grid, const Vec3& spacing,
                     bool gzip) {
  const int type = std::is_same_v<T, uint8_t>    ? nrrdTypeUChar
                   : std::is_same_v<T, uint16_t> ? nrrdTypeUShort
                                                 : nrrdTypeFloat;
  std::lock_guard lock(teemMutex());
  Nrrd* nrrd = nrrdNew();
  NrrdIoState* io = nrrdIoStateNew();
  // Teem does not write through the pointer; its C API takes it non-const.
  void* data = const_cast<T*>(grid.values.data());
  int failed = nrrdWrap_va(nrrd, data, type, 3, size_t(grid.size.x), size_t(grid.size.y),
                           size_t(grid.size.z));
  if (!failed) {
    nrrdAxisInfoSet_va(nrrd, nrrdAxisInfoSpacing, spacing.x, spacing.y, spacing.z);
    io->encoding = gzip ? nrrdEncodingGzip : nrrdEncodingRaw;
    failed = nrrdSave(path.c_str(), nrrd, io);
  }
  const std::string problem = failed ? teemProblem() : "";
  nrrdIoStateNix(io);
  nrrdNix(nrrd);  // the data stays the grid's
  if (failed) throw std::runtime_error("cannot write '" + path + "': " + problem);
}

template void writeNrrdVolume(const std::string&, const volume::DenseGrid<uint8_t>&, const Vec3&,
                              bool);
template void writeNrrdVolume(const std::string&, const volume::DenseGrid<uint16_t>&, const Vec3&,
                              bool);
template void writeNrrdVolume(const std::string&, const volume::DenseGrid<float>&, const Vec3&,
                              bool);

}  // namespace penumbra::protocol
