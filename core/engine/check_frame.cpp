// Engine::checkFrame: a frame is refused whole, before anything changes, when an edit would
// name an unknown or duplicate object, leave the overlap cubes or exceed the face budget.
#include <map>
#include <optional>
#include <set>
#include <string>

#include "core/engine/engine.h"
#include "core/engine/light_edits.h"
#include "core/engine/volume_edits.h"

namespace penumbra {

namespace {

// The ids a frame has edited so far, as its earlier edits leave them (nullopt: removed).
using EditedObjects = std::map<std::string, std::optional<Object>, std::less<>>;

// The scene's face count once the edited objects are as `edited` leaves them.
size_t facesAfter(const Scene& scene, const EditedObjects& edited) {
  size_t faces = scene.faces().size();
  for (const auto& [id, object] : edited) {
    if (const auto index = scene.findObject(id)) faces -= scene.objects()[*index].faces.size();
    if (object) faces += object->faces.size();
  }
  return faces;
}

// The last edit giving a light a new polygon, or adding one (a frame with none: 0).
size_t lastLightMove(const Frame& frame) {
  size_t last = 0;
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    if ((edit.op == Edit::Op::SetLight && edit.polygon) || edit.op == Edit::Op::AddLight) last = i;
  }
  return last;
}

// A frame reshaping the lights rebuilds every cube around them: the faces the frame leaves
// alone must lie in the new cubes too (OverlapCube::insertFace refuses others).
void checkUneditedFaces(const Scene& scene, const Frame& frame, const std::set<std::string, std::less<>>& edited,
                        const std::vector<OverlapCube::Box>& cubes) {
  for (const Face& face : scene.faces()) {
    const Object& object = scene.object(face.id.object);
    if (edited.count(object.id) || insideCubes(scene, face.polygon, cubes)) continue;
    const size_t i = lastLightMove(frame);
    const bool added = frame.edits[i].op == Edit::Op::AddLight;
    throw EditError(i, added ? "light.polygon" : "polygon",
                    "light '" + (added ? frame.edits[i].light.id : frame.edits[i].id) + "' would leave object '" + object.id +
                        "' outside its overlap cube (the lights' cubes enclose the scene)");
  }
}

}  // namespace

void Engine::checkFrame(const Frame& frame) const {
  // The ids the frame has edited so far, as the earlier edits leave them (empty: removed).
  EditedObjects edited;
  auto current = [&](const std::string& id) -> std::optional<Object> {
    if (const auto it = edited.find(id); it != edited.end()) return it->second;
    if (const auto index = scene_.findObject(id)) return scene_.objects()[*index];
    return std::nullopt;
  };
  // The overlap cubes are sound only for faces inside them (OverlapCube::insertFace): the
  // current ones, or those of the lights as the frame leaves them (a frame moving, adding
  // or removing a light rebuilds every cube).
  const bool lightMoved = reshapesLights(frame);
  std::vector<OverlapCube::Box> cubes;
  if (lightMoved) {
    cubes = cubesFor(scene_, lightsAfter(scene_, frame));
  } else {
    for (const auto& cube : cubes_) cubes.push_back({cube->cubeMin(), cube->cubeSide()});
  }
  std::vector<Light> lights = scene_.lights();  // as the frame's earlier light edits leave them
  // Faces as Scene::addObject / setTransform would make them (throws std::invalid_argument).
  auto checkFaces = [&](const Object& object, size_t i, const char* path) {
    for (const Face& face : scene_.facesOf(object, 0))
      if (!insideCubes(scene_, face.polygon, cubes))
        throw EditError(i, path, "object '" + object.id + "' would leave the edit volume");
  };
  VolumeEditCheck volumes(scene_);  // volumes as the frame's earlier edits leave them
  std::set<std::string, std::less<>> newMaterials;  // added by the frame's earlier edits
  auto objectExists = [&](const std::string& id) { return current(id).has_value(); };
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    const Edit& edit = frame.edits[i];
    try {
      if (volumes.concerns(edit)) {  // render-time only: no faces, no cubes
        volumes.check(edit, i, objectExists);
        continue;
      }
      switch (edit.op) {
        case Edit::Op::Move: {
          std::optional<Object> object = current(edit.id);
          if (!object) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          object->transform = edit.transform;
          checkFaces(*object, i, "transform");
          edited[edit.id] = std::move(object);
          break;
        }
        case Edit::Op::Remove:
          if (!current(edit.id)) throw EditError(i, "id", "unknown object '" + edit.id + "'");
          edited[edit.id] = std::nullopt;
          break;
        case Edit::Op::Add: {
          if (current(edit.object.id) || volumes.has(edit.object.id))
            throw EditError(i, "object.id", "duplicate object id '" + edit.object.id + "'");
          Object checked = edit.object;  // a material the frame adds is known from then on
          if (newMaterials.count(checked.material)) checked.material.clear();
          checkFaces(checked, i, "object");
          edited[edit.object.id] = edit.object;
          break;
        }
        case Edit::Op::SetMaterial:
          if (edit.material.id.empty()) throw EditError(i, "id", "a material needs an id");
          if (!scene_.findMaterial(edit.material.id)) newMaterials.insert(edit.material.id);
          break;
        case Edit::Op::SetLight:
        case Edit::Op::AddLight:
        case Edit::Op::RemoveLight:
          checkLightEdit(scene_, edit, i, lights);
          break;
        case Edit::Op::SetVolume:
        case Edit::Op::AddVolume:
          break;  // volumes.concerns() took them
      }
    } catch (const EditError&) {
      throw;
    } catch (const FaceError& error) {
      // An added object's face has a key path; a moved one is refused for its transform.
      if (edit.op == Edit::Op::Add)
        throw EditError(i, "object.faces[" + std::to_string(error.face()) + "]", error.problem());
      throw EditError(i, "transform", error.what());
    } catch (const std::invalid_argument& error) {
      throw EditError(i, edit.op == Edit::Op::Add ? "object" : "transform", error.what());
    }
  }
  if (lightMoved) {
    std::set<std::string, std::less<>> ids;
    for (const auto& [id, object] : edited) ids.insert(id);
    checkUneditedFaces(scene_, frame, ids, cubes);
  }
  budget_.checkFaces(facesAfter(scene_, edited));
}

}  // namespace penumbra
