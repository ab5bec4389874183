// Fuzz target: one edit frame as JSON text → protocol::frameFromJson against the tiny scene's
// materials → Engine::apply on a fresh engine of the tiny scene → validate + mesh. Refusals
// (ValidationError, EditError) are fine. Bounded so one input runs in milliseconds: at most 4
// edits, 64 faces per added object, and transforms within the engine's usual range (thin or
// huge scales are issue 12 item 3, handled on another branch: PENUMBRA_FUZZ_STRICT=1 lets them
// through, and also counts any other exception out of apply as a finding).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/engine/engine.h"
#include "fuzz_support.h"
#include "protocol/edits_json.h"
#include "protocol/json_text.h"

using namespace penumbra;

namespace {

bool tame(const Transform& t) {
  for (int i = 0; i < 3; ++i) {
    const double s = std::abs(t.scale[i]);
    if (s < 1e-2 || s > 1e2 || std::abs(t.translate[i]) > 1e2) return false;
  }
  return true;
}

bool bounded(const Frame& frame) {
  if (frame.edits.size() > 4) return false;
  for (const Edit& edit : frame.edits) {
    if (edit.op == Edit::Op::Add && (edit.object.faces.size() > 64 || edit.object.vertices.size() > 256))
      return false;
    const Transform& t = edit.op == Edit::Op::Add ? edit.object.transform : edit.transform;
    if (edit.op != Edit::Op::Remove && !fuzz::strict() && !tame(t)) return false;
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const Scene& scene = fuzz::tinyScene();
  Frame frame;
  try {
    frame = protocol::frameFromJson(protocol::parseJsonText(text, 64 * 1024, protocol::kMaxJsonDepth),
                                    &scene.materials());
  } catch (const protocol::ValidationError& e) {
    fuzz::note(std::string("refused: ") + e.what());
    return 0;
  }
  // The writer's round trip, on every frame the reader accepts.
  fuzz::check(protocol::frameFromJson(protocol::frameToJson(frame), &scene.materials()).edits.size() ==
                  frame.edits.size(),
              "frame JSON round trip lost edits");
  if (!bounded(frame)) return 0;

  Engine engine(scene);
  try {
    engine.apply(frame);
  } catch (const EditError& e) {
    fuzz::note(std::string("edit refused: ") + e.what());
    fuzz::check(engine.version() == 0, "a refused frame changed the engine's version");
    return 0;
  } catch (const std::exception& e) {
    fuzz::note(std::string("apply threw: ") + e.what());
    if (fuzz::strict()) fuzz::fail(std::string("Engine::apply threw: ") + e.what());
    return 0;
  }
  try {
    engine.validate();
  } catch (const std::logic_error& e) {
    fuzz::fail(std::string("engine invalid after an applied frame: ") + e.what());
  }
  fuzz::note("applied, mesh of " + std::to_string(engine.mesh().vertexCount()) + " vertices");
  return 0;
}
