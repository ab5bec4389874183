// Seeded edit-script generators over a generated "cubes in a room" scene (or any
// scene whose movable objects are not the room's floor/ceiling/wall_*): dragging
// one cube, moving a share of the faces, removing and re-adding, building up.
// Pure functions of (scene, options); thread-safe.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/engine/frame.h"
#include "core/scene/scene.h"

namespace penumbra {

struct EditScript {
  std::string name;           // "drag", "move-5pct", "remove-add", "build-up"
  std::vector<Frame> frames;  // applies to the scene it was generated from
  size_t editedFaces = 0;     // faces of the objects one frame edits (build-up: the largest)
  double faceShare = 0;       // editedFaces / the scene's faces
  std::string subject;        // drag: which cube, its size and light distance, the path length
};

// The objects a script may edit: every object but the room (floor, ceiling, wall_*).
std::vector<size_t> movableObjects(const Scene& scene);

// One free cube (nothing rests on it) standing on the floor slid in `frames` steps
// of at most 8 cm, turning 0.5° a step. If the scene has kSubjectCubeId
// (CubesSceneOptions::subjectCube) that cube, literally the same at every scene
// size; otherwise the one whose centre is closest to 1.5 m (horizontally) from the
// first light's centre. It moves along the clear direction (of 16) closest to
// round the light (for the subject: exactly tangential, its kept-clear corridor,
// up to 100 frames); if none is clear for the whole length, the next-closest
// cubes (16 in all; not for the subject), then the longest clear path. The seed's parity only picks which way round the light
// (even: the angle atan2(z, x) about the light grows; odd: it shrinks).
// Throws std::invalid_argument if the scene has no movable object.
EditScript dragScript(const Scene& scene, int frames, uint64_t seed);

// A seeded set of movable objects holding about `share` of the scene's faces
// (at least one object), moved together each frame by the same small offset
// (a small circle, absolute transforms).
EditScript moveShareScript(const Scene& scene, double share, int frames, uint64_t seed);

// `pairs` times: one frame removes a seeded movable object, the next adds it back.
EditScript removeAddScript(const Scene& scene, int pairs, uint64_t seed);

// Frame 1 removes every movable object (the empty room); then one frame per
// object adds it back as it was, up to `maxObjects` (0: all).
EditScript buildUpScript(const Scene& scene, int maxObjects);

// The scripts shipped in bench/edits/ for a small scene (drag 100 frames, move
// 1/5/10/30% of the faces 10 frames each, remove-add 5 pairs, build-up).
std::vector<EditScript> standardEditScripts(const Scene& scene, uint64_t seed);

}  // namespace penumbra
