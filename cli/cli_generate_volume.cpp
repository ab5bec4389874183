// `penumbra generate --volume FIELD`: a test field (scenegen/volume_fields) as a NRRD file,
// for scenes' volume objects (SCENE_FORMAT.md) and the tests.
#include <cstdio>

#include "cli/commands.h"
#include "protocol/nrrd_volume.h"
#include "scenegen/volume_fields.h"

namespace penumbra::cli {

namespace {

VolumeField fieldNamed(const std::string& name) {
  for (VolumeField field : kVolumeFields)
    if (volumeFieldName(field) == name) return field;
  throw UsageError("--volume '" + name + "': expected marschner-lobb, sphere, smoke or mixing");
}

}  // namespace

int runGenerateVolume(const Args& args) {
  args.allowOnly({"volume", "size", "seed", "type", "spacing", "out"});
  VolumeFieldSpec spec;
  spec.field = fieldNamed(*args.option("volume"));
  spec.size = glm::ivec3(args.intOption("size", 64, 2, 512));
  spec.seed = uint64_t(args.intOption("seed", int(spec.seed), 0, 1 << 30));
  const double spacing = args.doubleOption("spacing", 1.0 / (spec.size.x - 1));
  if (!(spacing > 0)) throw UsageError("--spacing must be positive");
  const std::string type = args.option("type").value_or("uchar");
  const auto out = args.option("out");
  if (!out) throw UsageError("generate --volume needs --out FILE.nrrd");

  const volume::DenseGrid<float> field = makeVolumeField(spec);
  if (type == "uchar")
    protocol::writeNrrdVolume(*out, quantise8(field), Vec3(spacing));
  else if (type == "ushort")
    protocol::writeNrrdVolume(*out, quantise16(field), Vec3(spacing));
  else if (type == "float")
    protocol::writeNrrdVolume(*out, field, Vec3(spacing));
  else
    throw UsageError("--type '" + type + "': expected uchar, ushort or float");
  std::printf("wrote %s: %s %d³ %s, spacing %g (gzip)\n", out->c_str(),
              volumeFieldName(spec.field).c_str(), spec.size.x, type.c_str(), spacing);
  return 0;
}

}  // namespace penumbra::cli
