// JSON <-> Material: the Lambertian albedo and the microfacet keys (type, roughness, eta, k,
// ior, ndf, scattering), validated with key-path errors. Free functions; thread-safe.
#pragma once

#include <string>

#include "core/scene/scene.h"
#include "protocol/json_reader.h"

namespace penumbra::protocol {

// body: the value of materials[name]; path: its key path. Throws ValidationError.
Material materialFromJson(const std::string& name, const Json& body, const std::string& path);
// A diffuse material writes {"albedo": …} only, as files before these keys did.
Json materialToJson(const Material& material);

}  // namespace penumbra::protocol
