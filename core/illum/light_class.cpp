#include "core/illum/light_class.h"

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

}  // namespace penumbra
