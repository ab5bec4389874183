#include "interchange/import_report.h"

#include "protocol/utf8.h"

namespace penumbra::interchange {

using protocol::replacingInvalidUtf8;

// Warnings and the source name quote the file's own bytes, which need not be UTF-8.
nlohmann::json ImportReport::toJson() const {
  nlohmann::json validWarnings = nlohmann::json::array();
  for (const std::string& warning : warnings) validWarnings.push_back(replacingInvalidUtf8(warning));
  return {{"source", replacingInvalidUtf8(source)},
          {"format", format},
          {"objects", objects},
          {"faces", faces},
          {"lights", lights},
          {"materials", materials},
          {"repairs", repairs},
          {"warnings", validWarnings}};
}

std::string ImportReport::summary() const {
  std::string text = source + " (" + format + "): " + std::to_string(objects) + " objects, " +
                     std::to_string(faces) + " faces, " + std::to_string(lights) + " lights, " +
                     std::to_string(materials) + " materials\n";
  if (repairs.empty()) text += "  no repairs\n";
  for (const auto& [repair, times] : repairs) text += "  repaired: " + repair + " × " + std::to_string(times) + "\n";
  for (const std::string& warning : warnings) text += "  warning: " + warning + "\n";
  return text;
}

}  // namespace penumbra::interchange
