// Scene's volume edits: render-time objects, so faces, bounds and tolerance never change.
#include <cmath>
#include <stdexcept>

#include "core/scene/scene.h"

namespace penumbra {

namespace {

void checkIndex(const std::vector<VolumeObject>& volumes, size_t index) {
  if (index >= volumes.size())
    throw std::invalid_argument("no volume at index " + std::to_string(index));
}

}  // namespace

void Scene::addVolume(VolumeObject volume) {
  if (!volume.data) throw std::invalid_argument("volume '" + volume.id + "' has no data");
  if (findObject(volume.id) || findVolume(volume.id))
    throw std::invalid_argument("duplicate object id '" + volume.id + "'");
  if (!volume.material.empty() && !findMaterial(volume.material))
    throw std::invalid_argument("volume '" + volume.id + "' names unknown material '" +
                                volume.material + "'");
  if (!std::isfinite(volume.isovalue))
    throw std::invalid_argument("volume '" + volume.id + "': isovalue is not finite");
  volumes_.push_back(std::move(volume));
}

void Scene::removeVolume(size_t index) {
  checkIndex(volumes_, index);
  volumes_.erase(volumes_.begin() + long(index));
}

void Scene::setVolumeTransform(size_t index, const Transform& transform) {
  checkIndex(volumes_, index);
  volumes_[index].transform = transform;
}

void Scene::setVolumeIsovalue(size_t index, double isovalue) {
  checkIndex(volumes_, index);
  if (!std::isfinite(isovalue)) throw std::invalid_argument("isovalue is not finite");
  volumes_[index].isovalue = isovalue;
}

}  // namespace penumbra
