// A frame of edits (SCENE_FORMAT.md edit scripts, already parsed) and what applying
// it did. Plain data; built by protocol or callers, consumed by Engine::apply.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/scene/scene.h"

namespace penumbra {

struct Edit {
  enum class Op { Move, Add, Remove, SetLight, AddLight, RemoveLight, SetVolume, AddVolume, SetMaterial };
  Op op = Op::Move;
  // move, remove: an existing object's id (a polygon object's or a volume's); add: object.id;
  // set_light, remove_light: an existing light's id; add_light: light.id; set_volume: an
  // existing volume's id; add_volume: volume.id; set_material: material.id
  std::string id;
  Transform transform;  // move: the new absolute transform
  Object object;        // add: the new object (transform included)
  // set_light: the light's new polygon and/or radiance (at least one); the other stays.
  std::optional<Polygon3> polygon;
  std::optional<Vec3> radiance;
  Light light;  // add_light: the new light, as in a scene's lights (it comes last)
  double isovalue = 0;  // set_volume: the volume's new isovalue
  VolumeObject volume;  // add_volume: the new volume, its data read (it comes last)
  // set_material: the material under its id, replacing the scene's of that id or added last. Only
  // the camera sees materials (albedo colours the irradiance view): no shadow work.
  Material material;
};

struct Frame {
  std::vector<Edit> edits;
};

struct FrameTimings {
  double remove = 0;   // seconds: faces leaving the order, cube and DM-trees
  double add = 0;      // faces entering them, shadows cast both ways
  double relight = 0;  // vertices relit
  double total() const { return remove + add + relight; }
};

struct FrameResult {
  uint64_t version = 0;            // the scene version after the frame
  FrameTimings seconds;
  size_t verticesRelit = 0;        // DM vertices illuminated again
  size_t verticesChanged = 0;      // of those, the ones whose value changed
  size_t verticesCreated = 0;      // new DM vertices (relit, counted in verticesRelit)
  std::vector<FaceId> changedReceivers;  // receivers whose mesh changed (ids in the new scene)
  std::vector<FaceId> removedReceivers;  // receivers that left the scene
  size_t nodesDeleted = 0;         // DM-tree nodes removed by node deletion
  size_t treeRebuilds = 0;         // fallback: receivers' DM-trees rebuilt from scratch
  // The frame undid more than a set share of a large scene's cast pairs or added more than a
  // set share of its faces (apply_frame.cpp: kFullRebuildPairShare, kFullRebuildAddedShare), or
  // moved, resized, turned, added or removed a light (orders,
  // cubes and every shadow change), so the engine was rebuilt instead (treeRebuilds =
  // every receiver).
  bool fullRebuild = false;
  // The frame changed a light's radiance only: every vertex's value was summed again from
  // its stored per-light factors (no geometry work; counted in verticesRelit/Changed).
  bool radianceChanged = false;
};

// A frame refused before anything changed: which edit, the key path inside it
// (e.g. "transform.scale"), and the problem; what() reads "<keyPath()>: <problem()>".
class EditError : public std::invalid_argument {
 public:
  EditError(size_t editIndex, std::string path, std::string problem)
      : std::invalid_argument(keyPathOf(editIndex, path) + ": " + problem),
        editIndex_(editIndex),
        path_(std::move(path)),
        problem_(std::move(problem)) {}
  size_t editIndex() const { return editIndex_; }
  // The key path inside the edit ("" for the edit itself).
  const std::string& path() const { return path_; }
  // The key path inside the frame: "edits[2].transform.scale".
  std::string keyPath() const { return keyPathOf(editIndex_, path_); }
  const std::string& problem() const { return problem_; }

 private:
  static std::string keyPathOf(size_t editIndex, const std::string& path) {
    return "edits[" + std::to_string(editIndex) + "]" + (path.empty() ? "" : "." + path);
  }

  size_t editIndex_;
  std::string path_;
  std::string problem_;
};

}  // namespace penumbra
