#include "server/frame_batch.h"

#include <set>
#include <string>

namespace penumbra::server {

std::optional<Frame> combinedFrame(const std::vector<const Frame*>& frames) {
  Frame combined;
  std::set<std::string> earlier;  // ids named by the frames before the current one
  for (const Frame* frame : frames) {
    std::set<std::string> mine;
    for (const Edit& edit : frame->edits) {
      if (earlier.count(edit.id)) return std::nullopt;
      mine.insert(edit.id);
      combined.edits.push_back(edit);
    }
    earlier.insert(mine.begin(), mine.end());
  }
  return combined;
}

}  // namespace penumbra::server
