#include "server/frame_cost.h"

#include "server/api_errors.h"

namespace penumbra::server {

uint64_t FrameCost::work() const {
  return lightChanges * lightsAfter * facesAfter + facesAdded * lightsAfter;
}

std::string FrameCost::describe() const {
  return std::to_string(lightChanges) + " light changes × " + std::to_string(lightsAfter) +
         " lights × " + std::to_string(facesAfter) + " faces + " + std::to_string(facesAdded) +
         " faces added × " + std::to_string(lightsAfter) + " lights = " + std::to_string(work());
}

FrameCost estimateFrameCost(const Scene& scene, const Frame& frame) {
  FrameCost cost;
  int64_t lights = int64_t(scene.lights().size());
  int64_t faces = int64_t(scene.faces().size());
  for (const Edit& edit : frame.edits) switch (edit.op) {
      case Edit::Op::AddLight:
        ++lights;
        ++cost.lightChanges;
        break;
      case Edit::Op::RemoveLight:
        --lights;
        break;
      case Edit::Op::SetLight:
        if (edit.polygon) ++cost.lightChanges;
        break;
      case Edit::Op::Add:
        faces += int64_t(edit.object.faces.size());
        cost.facesAdded += edit.object.faces.size();
        break;
      default:
        break;  // a move or remove costs what the moved faces cast: bounded by the scene
    }
  cost.lightsAfter = uint64_t(std::max<int64_t>(lights, 0));
  cost.facesAfter = uint64_t(std::max<int64_t>(faces, 0));
  return cost;
}

void refuseCostlyFrame(const FrameCost& cost, uint64_t maxWork) {
  if (cost.work() <= maxWork) return;
  throw ApiError(422, error_code::kFrameTooCostly, "edits",
                 "this frame's estimated work (" + cost.describe() +
                     ") is more than the server's limit of " + std::to_string(maxWork) +
                     " (serve --max-frame-work): send the lights in smaller frames");
}

}  // namespace penumbra::server
