// Wavefront OBJ + MTL → scene v1 (through tinyobjloader, double precision): groups
// and objects ('g', 'o') become objects, one per material; Kd → albedo; faces of an
// emissive material (Ke, or Ka on a material named like a light when it has no Ke)
// become area lights. Free functions; thread-safe (no shared state).
#pragma once

#include <map>
#include <string>

#include "interchange/scene_assembly.h"

namespace penumbra::interchange {

// Reads the file and the MTL files its 'mtllib' lines name, beside it. A missing
// MTL file is a repair (its materials take the default albedo), not an error.
// Throws protocol::ValidationError (path "(obj)" or "(import)") for input that
// gives no scene, std::runtime_error when the file cannot be read.
ImportResult importObjFile(const std::string& path, const ImportOptions& options);

// The same from memory (an upload): `mtlFiles` maps the names 'mtllib' uses to
// their text; names it lacks count as missing. `sourceName` goes into the report.
ImportResult importObjText(const std::string& objText, const std::map<std::string, std::string>& mtlFiles,
                           const ImportOptions& options, const std::string& sourceName);

// "light", "Light_01", "ceilingLamp", "emitter": material names treated as lights
// when they carry Ka but no Ke (the classic Cornell box files).
bool namedLikeALight(const std::string& materialName);

}  // namespace penumbra::interchange
