#include "core/engine/volume_edits.h"

#include <cmath>
#include <cstdio>

namespace penumbra {

namespace {

// A volume's transform must map voxels somewhere: finite, no zero scale (the protocol refuses
// these too; the check is here for frames built in code).
void checkTransform(const Transform& transform, size_t index) {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(transform.translate[a]) || !std::isfinite(transform.rotateDeg[a]) ||
        !std::isfinite(transform.scale[a]))
      throw EditError(index, "transform", "not finite");
    if (transform.scale[a] == 0) throw EditError(index, "transform.scale", "a zero scale");
  }
}

std::string rangeText(const volume::ScalarVolume& data) {
  char text[96];
  std::snprintf(text, sizeof text, "[%.9g, %.9g]", data.minValue(), data.maxValue());
  return text;
}

}  // namespace

std::optional<std::string> isovalueProblem(const volume::ScalarVolume& data, double isovalue) {
  if (!std::isfinite(isovalue)) return "isovalue is not finite";
  if (isovalue < data.minValue() || isovalue > data.maxValue())
    return "isovalue is outside the volume's values " + rangeText(data) + " (no surface there)";
  return std::nullopt;
}

VolumeEditCheck::VolumeEditCheck(const Scene& scene) : scene_(scene) {
  for (const VolumeObject& volume : scene.volumes()) volumes_[volume.id] = volume.data;
}

bool VolumeEditCheck::concerns(const Edit& edit) const {
  if (edit.op == Edit::Op::SetVolume || edit.op == Edit::Op::AddVolume) return true;
  return (edit.op == Edit::Op::Move || edit.op == Edit::Op::Remove) && has(edit.id);
}

void VolumeEditCheck::check(const Edit& edit, size_t index,
                            const std::function<bool(const std::string&)>& objectExists) {
  switch (edit.op) {
    case Edit::Op::Move:
      checkTransform(edit.transform, index);
      return;
    case Edit::Op::Remove:
      volumes_.erase(edit.id);
      return;
    case Edit::Op::SetVolume: {
      const auto it = volumes_.find(edit.id);
      if (it == volumes_.end()) {
        const std::string what = objectExists(edit.id) ? "'" + edit.id + "' is not a volume"
                                                       : "unknown volume '" + edit.id + "'";
        throw EditError(index, "id", what);
      }
      if (const auto problem = isovalueProblem(*it->second, edit.isovalue))
        throw EditError(index, "isovalue", *problem);
      return;
    }
    case Edit::Op::AddVolume: {
      const VolumeObject& volume = edit.volume;
      if (has(volume.id) || objectExists(volume.id))
        throw EditError(index, "volume.id", "duplicate object id '" + volume.id + "'");
      if (!volume.data) throw EditError(index, "volume", "the volume has no data");
      if (!volume.material.empty() && !scene_.findMaterial(volume.material))
        throw EditError(index, "volume.material", "unknown material '" + volume.material + "'");
      if (const auto problem = isovalueProblem(*volume.data, volume.isovalue))
        throw EditError(index, "volume.isovalue", *problem);
      try {
        checkTransform(volume.transform, index);
      } catch (const EditError& error) {
        throw EditError(index, "volume." + error.path(), "not finite or a zero scale");
      }
      volumes_[volume.id] = volume.data;
      return;
    }
    default:
      throw EditError(index, "op", "not a volume edit");
  }
}

void applyVolumeEdit(Scene& scene, const Edit& edit) {
  if (edit.op == Edit::Op::AddVolume) return scene.addVolume(edit.volume);
  const auto index = scene.findVolume(edit.id);
  if (!index) throw std::invalid_argument("unknown volume '" + edit.id + "'");
  switch (edit.op) {
    case Edit::Op::Move:
      return scene.setVolumeTransform(*index, edit.transform);
    case Edit::Op::Remove:
      return scene.removeVolume(*index);
    case Edit::Op::SetVolume:
      return scene.setVolumeIsovalue(*index, edit.isovalue);
    default:
      throw std::invalid_argument("not a volume edit");
  }
}

}  // namespace penumbra
