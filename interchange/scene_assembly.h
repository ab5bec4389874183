// Imported polygon groups → a validated scene v1: scale, weld, repair polygons,
// drop duplicate faces, emissive polygons → lights (turned to face the scene),
// unique ids; every change counted in the report. Free function; thread-safe.
#pragma once

#include <nlohmann/json.hpp>

#include "core/scene/scene.h"
#include "interchange/import_report.h"
#include "interchange/imported_geometry.h"

namespace penumbra::interchange {

struct ImportResult {
  nlohmann::json sceneJson;  // scene v1, exactly what `scene` was validated from
  Scene scene;
  ImportReport report;
};

// Throws protocol::ValidationError (path "(import)" or the option's name) when no
// usable scene results: no faces, no light, a bad scale.
ImportResult assembleScene(const ImportedGeometry& geometry, const ImportOptions& options,
                           ImportReport report);

}  // namespace penumbra::interchange
