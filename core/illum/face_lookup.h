// Finding a scene face by its stable id (Scene::faces() is sorted by FaceId).
// Free function on a const Scene; thread-safe.
#pragma once

#include <algorithm>

#include "core/scene/scene.h"

namespace penumbra {

// The face with this id, or nullptr if the scene has none (a stale list entry).
inline const Face* findFace(const Scene& scene, FaceId id) {
  const std::vector<Face>& faces = scene.faces();
  const auto it = std::lower_bound(faces.begin(), faces.end(), id,
                                   [](const Face& f, FaceId key) { return f.id < key; });
  return it != faces.end() && it->id == id ? &*it : nullptr;
}

// The normal point p of face `id` is shaded with: its corner normals interpolated
// (shading_normal.h), or `flat`, the face's own normal, when it has none.
inline Vec3 shadingNormalAt(const Scene& scene, FaceId id, const Vec3& flat, const Vec3& p) {
  const Face* face = findFace(scene, id);
  return face && !face->cornerNormals.empty() ? interpolatedNormal(face->polygon, face->cornerNormals, flat, p)
                                              : flat;
}

}  // namespace penumbra
