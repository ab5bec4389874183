// The compact binary mesh (docs/API.md "Binary"): little-endian typed arrays, 4-byte
// aligned, that the page views in place. Free functions; thread-safe.
#pragma once

#include <cstdint>
#include <string>

#include "server/indirect_cache.h"
#include "server/scene_snapshot.h"

namespace penumbra::server::mesh_binary {

inline constexpr char kMagic[4] = {'P', 'N', 'M', 'B'};
// Layout 3 added values-only parts (a part whose irradiance alone changed: its new irradiance,
// no geometry); layout 4 sends a part's irradiance as one value per vertex and a tint when its
// vertices are one colour scaled (tinted_irradiance.h). A reader of another layout refuses it by
// the version rather than misread it.
inline constexpr uint32_t kLayoutVersion = 4;
inline constexpr size_t kHeaderBytes = 44;
inline constexpr size_t kPartRecordBytes = 56;
inline constexpr size_t kValuePartRecordBytes = 40;
inline constexpr size_t kRemovedRecordBytes = 16;
inline constexpr uint32_t kFlagDelta = 1;  // header flags: a `since` delta, not the whole mesh
// header flags: each part's irradiance is followed by its indirect irradiance (f32[3V]); only
// when the request asked (indirect=1), so readers of layout 2 without it see the same bytes.
inline constexpr uint32_t kFlagIndirect = 2;
// Class codes in the classes array.
inline constexpr uint8_t kLit = 0, kPenumbra = 1, kUmbra = 2;

// Encodes the selected parts (receivers' display chunks; valueParts as their irradiance alone)
// of a snapshot, with each vertex's indirect irradiance when `indirect` (a bake of this
// snapshot) is given. Throws std::overflow_error if a count or version does not fit 32 bits.
std::string encode(const SceneSnapshot& snapshot, const MeshSelection& selection,
                   const IndirectBake* indirect = nullptr);

}  // namespace penumbra::server::mesh_binary
