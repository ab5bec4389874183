#include "server/frame_batch.h"

#include <set>
#include <string>

#include "core/engine/light_edits.h"

namespace penumbra::server {

std::optional<Frame> combinedFrame(const std::vector<const Frame*>& frames) {
  Frame combined;
  std::set<std::string> earlier;  // ids named by the frames before the current one
  for (const Frame* frame : frames) {
    std::set<std::string> mine;
    for (const Edit& edit : frame->edits) {
      // Lights and objects are named apart: "lamp" the light is not "lamp" the object.
      const char* kind = isLightEdit(edit)                         ? "light:"
                         : edit.op == Edit::Op::SetMaterial ? "material:"
                                                            : "object:";
      const std::string name = kind + edit.id;
      if (earlier.count(name)) return std::nullopt;
      mine.insert(name);
      combined.edits.push_back(edit);
    }
    earlier.insert(mine.begin(), mine.end());
  }
  return combined;
}

bool isHeavyFrame(const Frame& frame) {
  for (const Edit& edit : frame.edits) switch (edit.op) {
      case Edit::Op::AddLight:
      case Edit::Op::AddVolume:
      case Edit::Op::SetVolume:
        return true;
      case Edit::Op::SetLight:
        if (edit.polygon) return true;  // a radiance alone re-sums the lights' values
        break;
      case Edit::Op::Add:
        if (edit.object.faces.size() > kHeavyObjectFaces) return true;
        break;
      default:
        break;
    }
  return false;
}

}  // namespace penumbra::server
