// A DM-tree cell's occluder list for one light: the faces that hide the light
// from the cell, fully (umbra, flagged and kept at the head) or partly.
// Plain data owned by its cell; read-only outside core/dmtree.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geom/fingerprint.h"
#include "core/scene/scene.h"

namespace penumbra {

// 12 bytes, not 16: the umbra flag shares the light index's word. Dense rooms keep ~40
// entries in each of millions of cells, so this is a good part of a build's memory.
struct OccluderEntry {
  OccluderEntry() = default;
  OccluderEntry(uint32_t light, FaceId face, bool umbra = false) : light(light), umbra(umbra), face(face) {}
  uint32_t light : 31 = 0;
  uint32_t umbra : 1 = 0;  // the face hides the whole light from the cell
  FaceId face;
  bool operator==(const OccluderEntry&) const = default;
};
static_assert(sizeof(OccluderEntry) == 12);

// Adds an entry to a fingerprint as two words (the occluder list pool's hash, the mesh memo's).
inline void addEntry(Fingerprint& f, const OccluderEntry& e) {
  f.add(uint64_t(e.light) << 1 | uint64_t(e.umbra));
  f.add(uint64_t(e.face.object) << 32 | uint64_t(e.face.face));
}

// The occluder of a light's own plane: where that plane cuts a receiver, the part
// behind it gets no light (lights emit from their front only). Not a scene face.
inline constexpr FaceId kLightPlaneOccluder{0xffffffffu, 0xffffffffu};

// Umbra entries first (paper §2.4), then partial ones; at most one entry per
// (light, face).
using OccluderList = std::vector<OccluderEntry>;

// Whether the list holds an umbra entry for `light` (the cell lies in one of its umbras).
inline bool hasUmbraEntry(const OccluderList& list, uint32_t light) {
  for (const OccluderEntry& e : list) {
    if (!e.umbra) return false;  // umbra entries come first
    if (e.light == light) return true;
  }
  return false;
}

}  // namespace penumbra
