// Test helpers for degenerate geometry: the cubes15 demo scene as JSON, engine
// settings whose limits bound a build to a multiple of a baseline, and a sampled
// comparison of an engine's DM vertices with the exact reference.
#pragma once

#include <fstream>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "core/engine/engine.h"
#include "core/illum/face_lookup.h"
#include "core/reference/exact_irradiance.h"
#include "protocol/scene_json.h"
#include "tests/core/engine/incremental_compare.h"

namespace penumbra::testing {

inline nlohmann::json cubes15Json() {
  std::ifstream in(std::string(PENUMBRA_SOURCE_DIR) + "/scenes/cubes15.scene.json");
  return nlohmann::json::parse(in);
}

// Limits at `factor` × the baseline's tree nodes and vertices: a build or frame that
// would run away throws ResourceLimitError instead of eating the machine.
// cubes15's tree usage, built once: the unit the bounded settings are multiples of.
inline TreeUsage baselineUsage() {
  static const TreeUsage usage = Engine(protocol::sceneFromJson(cubes15Json())).resourceUsage();
  return usage;
}

inline EngineSettings boundedSettings(const TreeUsage& baseline, size_t factor) {
  EngineSettings settings;
  settings.limits.treeNodes = factor * baseline.nodes;
  settings.limits.vertices = factor * baseline.vertices;
  return settings;
}

// DM vertices (up to `samples`, seeded) whose value differs from the exact reference
// by more than the engine tests allow (1e-9 relative + 1e-12 of the peak).
inline size_t referenceMismatches(const Engine& engine, size_t samples, uint64_t seed) {
  const ExactReference reference(engine.scene());
  const double peak = peakIrradiance(engine);
  std::mt19937_64 rng(seed);
  size_t total = 0;
  for (const auto& r : engine.receivers()) total += r.tree.vertexCount();
  const double keep = total <= samples ? 1.0 : double(samples) / double(total);
  std::bernoulli_distribution pick(keep);
  size_t errors = 0;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) {
      if (!pick(rng)) continue;
      const Vec3 p = r.frame.to3D(r.tree.position(v));
      const PointIrradiance truth =
          reference.evaluate(p, r.frame.normal, shadingNormalAt(engine.scene(), r.face, r.frame.normal, p));
      for (int c = 0; c < 3; ++c)
        if (std::abs(engine.value(r, v).irradiance[c] - truth.irradiance[c]) >
            1e-9 * std::abs(truth.irradiance[c]) + 1e-12 * peak) {
          if (errors++ < 3)
            ADD_FAILURE() << "face " << r.face.object << "/" << r.face.face << " at (" << p.x << ", " << p.y
                          << ", " << p.z << "): engine " << engine.value(r, v).irradiance[c] << ", reference "
                          << truth.irradiance[c];
          break;
        }
    }
  return errors;
}

}  // namespace penumbra::testing
