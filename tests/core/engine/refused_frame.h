// Test helpers for frames the engine must refuse: the scene and mesh as text, and the check that
// a refused frame names its edit and key path and leaves version, scene and mesh as they were.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "core/engine/engine.h"
#include "protocol/mesh_json.h"
#include "protocol/scene_json.h"

namespace penumbra::testing {

inline std::string meshText(Engine& engine) {
  return protocol::meshToJson(engine.scene(), engine.mesh(), "s").dump();
}

inline std::string sceneText(const Engine& engine) {
  return protocol::sceneToJson(engine.scene()).dump();
}

inline void expectRefusedUnchanged(Engine& engine, const Frame& frame, size_t editIndex,
                                   const std::string& path) {
  const uint64_t version = engine.version();
  const std::string scene = sceneText(engine), mesh = meshText(engine);
  try {
    engine.apply(frame);
    ADD_FAILURE() << "frame accepted";
  } catch (const EditError& error) {
    EXPECT_EQ(error.editIndex(), editIndex) << error.what();
    EXPECT_EQ(error.path(), path) << error.what();
  }
  EXPECT_EQ(engine.version(), version);
  EXPECT_EQ(sceneText(engine), scene);
  EXPECT_TRUE(meshText(engine) == mesh) << "mesh changed";
  EXPECT_NO_THROW(engine.validate());
}

}  // namespace penumbra::testing
