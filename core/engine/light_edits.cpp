#include "core/engine/light_edits.h"

#include <chrono>
#include <cstdio>
#include <set>

#include "core/engine/engine.h"
#include "core/illum/light_sum.h"

namespace penumbra {

bool isLightEdit(const Edit& edit) {
  return edit.op == Edit::Op::SetLight || edit.op == Edit::Op::AddLight ||
         edit.op == Edit::Op::RemoveLight;
}

bool reshapesLights(const Frame& frame) {
  for (const Edit& edit : frame.edits)
    if ((edit.op == Edit::Op::SetLight && edit.polygon) || edit.op == Edit::Op::AddLight ||
        edit.op == Edit::Op::RemoveLight)
      return true;
  return false;
}

bool changesRadiance(const Frame& frame) {
  for (const Edit& edit : frame.edits)
    if (edit.op == Edit::Op::SetLight && edit.radiance) return true;
  return false;
}

Light editedLight(const Light& light, const Edit& edit) {
  Light out = light;
  if (edit.polygon) out.polygon = *edit.polygon;
  if (edit.radiance) out.radiance = *edit.radiance;
  return out;
}

namespace {

std::optional<size_t> findIn(const std::vector<Light>& lights, const std::string& id) {
  for (size_t l = 0; l < lights.size(); ++l)
    if (lights[l].id == id) return l;
  return std::nullopt;
}

// The space a light may take: where objects may go (OverlapCubeSettings::editVolume's
// default), so the tolerance and the cubes keep the scene's scale.
Bounds lightVolume(const Scene& scene) {
  const double margin = OverlapCubeSettings::kDefaultEditMargin * scene.bounds().diagonal();
  return Bounds{scene.bounds().min - Vec3(margin), scene.bounds().max + Vec3(margin)};
}

// A light polygon the scene can take, inside the edit volume; `path` names the polygon
// ("polygon", "light.polygon").
void checkPolygon(const Scene& scene, const Polygon3& polygon, const std::string& lightId,
                  size_t index, const std::string& path) {
  if (const auto problem = Scene::lightProblem(polygon, scene.tolerance()))
    throw EditError(index, path, *problem);
  const Bounds volume = lightVolume(scene);
  const double eps = scene.tolerance().length();
  for (size_t v = 0; v < polygon.size(); ++v) {
    const Vec3& p = polygon[v];
    if (glm::any(glm::lessThan(p, volume.min - Vec3(eps))) ||
        glm::any(glm::greaterThan(p, volume.max + Vec3(eps)))) {
      char text[200];
      std::snprintf(text, sizeof text, "[%.4g, %.4g, %.4g]–[%.4g, %.4g, %.4g]", volume.min.x,
                    volume.min.y, volume.min.z, volume.max.x, volume.max.y, volume.max.z);
      throw EditError(index, path + "[" + std::to_string(v) + "]",
                      "light '" + lightId + "' would leave the edit volume " + text);
    }
  }
}

void checkRadiance(const Vec3& radiance, size_t index, const std::string& path) {
  if (const auto problem = Scene::radianceProblem(radiance)) throw EditError(index, path, *problem);
}

}  // namespace

void checkLightEdit(const Scene& scene, const Edit& edit, size_t index,
                    std::vector<Light>& lights) {
  if (edit.op == Edit::Op::AddLight) {
    const Light& light = edit.light;
    if (findIn(lights, light.id))
      throw EditError(index, "light.id", "duplicate light id '" + light.id + "'");
    checkPolygon(scene, light.polygon, light.id, index, "light.polygon");
    checkRadiance(light.radiance, index, "light.radiance");
    lights.push_back(light);
    return;
  }
  const auto l = findIn(lights, edit.id);
  if (!l) throw EditError(index, "id", "unknown light '" + edit.id + "'");
  if (edit.op == Edit::Op::RemoveLight) {
    if (lights.size() == 1)
      throw EditError(index, "id",
                      "cannot remove light '" + edit.id + "': a scene keeps at least one light");
    lights.erase(lights.begin() + std::ptrdiff_t(*l));
    return;
  }
  if (!edit.polygon && !edit.radiance)
    throw EditError(index, "", "set_light changes nothing: give \"polygon\", \"radiance\" or both");
  if (edit.polygon) checkPolygon(scene, *edit.polygon, edit.id, index, "polygon");
  if (edit.radiance) checkRadiance(*edit.radiance, index, "radiance");
  lights[*l] = editedLight(lights[*l], edit);
}

void applyLightEdit(Scene& scene, const Edit& edit) {
  switch (edit.op) {
    case Edit::Op::AddLight:
      scene.addLight(edit.light);
      break;
    case Edit::Op::RemoveLight:
      scene.removeLight(*scene.findLight(edit.id));
      break;
    default: {
      const size_t l = *scene.findLight(edit.id);
      const Light light = editedLight(scene.lights()[l], edit);
      scene.setLight(l, light.polygon, light.radiance);
    }
  }
}

std::vector<Light> lightsAfter(const Scene& scene, const Frame& frame) {
  std::vector<Light> lights = scene.lights();
  for (size_t i = 0; i < frame.edits.size(); ++i) {
    if (!isLightEdit(frame.edits[i])) continue;
    try {
      checkLightEdit(scene, frame.edits[i], i, lights);
    } catch (const EditError&) {
      // refused in order by the frame's check
    }
  }
  return lights;
}

std::vector<OverlapCube::Box> cubesFor(const Scene& scene, const std::vector<Light>& lights) {
  std::vector<OverlapCube::Box> cubes;
  for (const Light& light : lights)
    cubes.push_back(OverlapCube::enclosingCube(scene, light.polygon));
  return cubes;
}

bool insideCubes(const Scene& scene, const Polygon3& polygon,
                 const std::vector<OverlapCube::Box>& cubes) {
  const double eps = scene.tolerance().length();
  for (const OverlapCube::Box& cube : cubes)
    for (const Vec3& v : polygon) {
      const Vec3 rel = v - cube.min;
      if (glm::any(glm::lessThan(rel, Vec3(-eps))) ||
          glm::any(glm::greaterThan(rel, Vec3(cube.side + eps))))
        return false;
    }
  return true;
}

}  // namespace penumbra

namespace penumbra {

void Engine::resumRadiance(const std::vector<Vec3>& radianceBefore, FrameResult& result) {
  const auto start = std::chrono::steady_clock::now();
  std::set<FaceId> changed(result.changedReceivers.begin(), result.changedReceivers.end());
  for (Receiver& receiver : receivers_) {
    std::vector<VertexId>& relit = lastRelit_[receiver.face];
    relit.clear();
    const bool sameLights = radianceBefore.size() == receiver.perLight.lightCount();
    changed.insert(receiver.face);
    if (receiver.fromLattice) continue;  // no values kept: its squares are summed again
    for (VertexId v : receiver.tree.vertices()) {
      const VertexIrradiance now = value(receiver, v);
      const VertexIrradiance old = sameLights ? sumLights(radianceBefore, receiver.perLight[v.index]) : VertexIrradiance{};
      relit.push_back(v);
      ++result.verticesRelit;
      if (!sameLights || !sameValue(old, now)) ++result.verticesChanged;
    }
  }
  // No cell is touched: the display memo keeps each light's value and sums the chunks again
  // with the new radiances when it is next brought up to date (mesh_memo.h).
  result.changedReceivers.assign(changed.begin(), changed.end());
  result.seconds.relight +=
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace penumbra
