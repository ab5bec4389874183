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
      const std::string name = (isLightEdit(edit) ? "light:" : "object:") + edit.id;
      if (earlier.count(name)) return std::nullopt;
      mine.insert(name);
      combined.edits.push_back(edit);
    }
    earlier.insert(mine.begin(), mine.end());
  }
  return combined;
}

}  // namespace penumbra::server
