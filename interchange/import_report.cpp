#include "interchange/import_report.h"

namespace penumbra::interchange {

nlohmann::json ImportReport::toJson() const {
  return {{"source", source},   {"format", format},       {"objects", objects},
          {"faces", faces},     {"lights", lights},       {"materials", materials},
          {"repairs", repairs}, {"warnings", warnings}};
}

std::string ImportReport::summary() const {
  std::string text = source + " (" + format + "): " + std::to_string(objects) + " objects, " +
                     std::to_string(faces) + " faces, " + std::to_string(lights) + " lights, " +
                     std::to_string(materials) + " materials\n";
  if (repairs.empty()) text += "  no repairs\n";
  for (const auto& [repair, times] : repairs) text += "  repaired: " + repair + " × " + std::to_string(times) + "\n";
  for (const std::string& warning : warnings) text += "  loader warning: " + warning + "\n";
  return text;
}

}  // namespace penumbra::interchange
