#include "core/mesh/mesh.h"

namespace penumbra {

const char* toString(LightClass c) {
  switch (c) {
    case LightClass::Lit: return "lit";
    case LightClass::Penumbra: return "penumbra";
    case LightClass::Umbra: return "umbra";
  }
  return "?";
}

LightClass combine(LightClass a, LightClass b) { return a == b ? a : LightClass::Penumbra; }

size_t Mesh::vertexCount() const {
  size_t n = 0;
  for (const auto& r : receivers) n += r.positions.size();
  return n;
}

size_t Mesh::triangleCount() const {
  size_t n = 0;
  for (const auto& r : receivers) n += r.triangles.size();
  return n;
}

}  // namespace penumbra
