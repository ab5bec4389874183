// Test helper: every DM vertex of a built engine against the independent exact reference
// (DESIGN.md invariant 1) and the triangles tiling every receiver. Header-only; test use.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/engine/engine.h"
#include "core/illum/face_lookup.h"
#include "core/reference/exact_irradiance.h"

namespace penumbra::testing {

struct ReferenceCheck {
  size_t vertices = 0, valueErrors = 0, classErrors = 0;
};

// Values within 1e-9 relative + 1e-12 of the peak; classes equal unless either side is
// penumbra (a vertex on a shadow boundary may take either neighbouring class). Reports
// the first few failures with `label`.
inline ReferenceCheck checkAgainstReference(Engine& engine, const std::string& label) {
  const Mesh& mesh = engine.mesh();
  const ExactReference reference(engine.scene());
  double peak = 0;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) peak = std::max(peak, engine.value(r, v).irradiance.x);
  ReferenceCheck out;
  for (const Engine::Receiver& r : engine.receivers())
    for (VertexId v : r.tree.vertices()) {
      const Vec3 p = r.frame.to3D(r.tree.position(v));
      const PointIrradiance truth =
          reference.evaluate(p, r.frame.normal, shadingNormalAt(engine.scene(), r.face, r.frame.normal, p));
      const VertexIrradiance& value = engine.value(r, v);
      ++out.vertices;
      const double error = std::abs(value.irradiance.x - truth.irradiance.x);
      if (error > 1e-9 * std::abs(truth.irradiance.x) + 1e-12 * peak && out.valueErrors++ < 5)
        ADD_FAILURE() << label << " face " << r.face.object << "/" << r.face.face << " vertex "
                      << v.index << ": engine " << value.irradiance.x << " reference "
                      << truth.irradiance.x;
      const bool boundary =
          value.lightClass == LightClass::Penumbra || truth.lightClass == LightClass::Penumbra;
      if (value.lightClass != truth.lightClass && !boundary && out.classErrors++ < 5)
        ADD_FAILURE() << label << " class " << toString(value.lightClass) << " vs "
                      << toString(truth.lightClass);
    }
  for (const ReceiverMesh& r : mesh.receivers) {
    double sum = 0, faceArea = 0;
    for (const auto& t : r.triangles)
      sum += 0.5 * glm::length(glm::cross(r.positions[t[1]] - r.positions[t[0]],
                                          r.positions[t[2]] - r.positions[t[0]]));
    for (const Face& f : engine.scene().faces())
      if (f.id == r.face) faceArea = f.area;
    EXPECT_NEAR(sum, faceArea, 1e-9 * faceArea) << label;
  }
  return out;
}

}  // namespace penumbra::testing
