#include "interchange/default_studio.h"

#include <algorithm>
#include <sstream>
#include <utility>
#include <vector>

#include "core/geom/polygon.h"

namespace penumbra::interchange {

namespace {

using Json = nlohmann::json;

Json toJson(const Vec3& v) { return Json::array({v.x, v.y, v.z}); }

// The quad's corners wound counter-clockwise seen from `front` (scene v1's front side).
Json facing(Polygon3 quad, const Vec3& front) {
  if (glm::dot(newellVector(quad), front) < 0) std::reverse(quad.begin(), quad.end());
  Json points = Json::array();
  for (const Vec3& p : quad) points.push_back(toJson(p));
  return points;
}

std::string number(double value) {
  std::ostringstream text;
  text.precision(4);
  text << value;
  return text.str();
}

}  // namespace

StudioPlacement placeInStudio(const Bounds& model) {
  StudioPlacement placement;
  const Vec3 size = model.max - model.min;
  placement.extentBefore = std::max({size.x, size.y, size.z});
  if (placement.extentBefore > 0 &&
      (placement.extentBefore < kStudioMinFit || placement.extentBefore > kStudioMaxFit))
    placement.scale = kStudioFitExtent / placement.extentBefore;
  // The lowest corner lands on y = 0 exactly.
  placement.anchor =
      Vec3(0.5 * (model.min.x + model.max.x), model.min.y, 0.5 * (model.min.z + model.max.z));
  return placement;
}

Json studioLight(const std::string& id, const Vec3& radiance) {
  const double h = kStudioLightSide / 2, y = kStudioLightY;
  return {{"id", id},
          {"polygon", facing({{-h, y, -h}, {h, y, -h}, {h, y, h}, {-h, y, h}}, Vec3(0, -1, 0))},
          {"radiance", toJson(radiance)}};
}

Json studioRoom(const std::string& prefix, const std::string& material) {
  const double x = kStudioHalfSide, z = kStudioHalfSide, y = kStudioHeight;
  const std::vector<std::pair<std::string, Json>> quads = {
      {"floor", facing({{-x, 0, -z}, {x, 0, -z}, {x, 0, z}, {-x, 0, z}}, {0, 1, 0})},
      {"ceiling", facing({{-x, y, -z}, {x, y, -z}, {x, y, z}, {-x, y, z}}, {0, -1, 0})},
      {"wall_n", facing({{-x, 0, -z}, {x, 0, -z}, {x, y, -z}, {-x, y, -z}}, {0, 0, 1})},
      {"wall_s", facing({{-x, 0, z}, {x, 0, z}, {x, y, z}, {-x, y, z}}, {0, 0, -1})},
      {"wall_e", facing({{x, 0, -z}, {x, 0, z}, {x, y, z}, {x, y, -z}}, {-1, 0, 0})},
      {"wall_w", facing({{-x, 0, -z}, {-x, 0, z}, {-x, y, z}, {-x, y, -z}}, {1, 0, 0})},
  };
  Json room = Json::array();
  for (const auto& [name, vertices] : quads)
    room.push_back({{"id", prefix + name},
                    {"vertices", vertices},
                    {"faces", Json::array({Json::array({0, 1, 2, 3})})},
                    {"material", material},
                    {"static", true}});
  return room;
}

Json studioCamera(const Bounds& placedModel) {
  const Vec3 target = placedModel.center();
  return {{"position", toJson(Vec3(0, 1.6, kStudioHalfSide - 0.25))},
          {"target", toJson(target)},
          {"up", toJson(Vec3(0, 1, 0))},
          {"fov_y_deg", 60},
          {"far", 8 * kStudioHalfSide}};
}

std::string studioSentence(const std::string& source, const StudioPlacement& placement) {
  std::string text = "no lights in " + source + ": placed it in the default studio (" +
                     number(2 * kStudioHalfSide) + " × " + number(kStudioHeight) + " × " +
                     number(2 * kStudioHalfSide) + " m room, " +
                     number(kStudioLightSide * kStudioLightSide) + " m² light just under the " +
                     number(kStudioHeight) + " m ceiling), ";
  if (placement.scale != 1)
    text += "scaled by " + number(placement.scale) + " (largest extent " +
            number(placement.extentBefore) + " → " +
            number(placement.extentBefore * placement.scale) + " m)";
  else
    text += "not scaled (largest extent " + number(placement.extentBefore) + " m, within " +
            number(kStudioMinFit) + "–" + number(kStudioMaxFit) + " m)";
  return text + ", resting on the floor at the room's centre";
}

}  // namespace penumbra::interchange
