#include "cli/cli_args.h"
#include "cli/commands.h"
#include "core/engine/engine.h"

#include <charconv>
#include <cmath>

namespace penumbra::cli {

Args::Args(int argc, char** argv, int first, std::set<std::string> flags) {
  for (int i = first; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg.rfind("--", 0) != 0 || arg.size() == 2) {
      positionals_.push_back(arg);
      continue;
    }
    const std::string name = arg.substr(2);
    if (flags.count(name)) {
      flags_.insert(name);
    } else if (i + 1 < argc) {
      options_.emplace_back(name, argv[++i]);
    } else {
      throw UsageError("option --" + name + " needs a value");
    }
  }
}

std::string Args::positional(size_t index, const char* what) const {
  if (index >= positionals_.size()) throw UsageError(std::string("missing ") + what);
  return positionals_[index];
}

std::optional<std::string> Args::option(const std::string& name) const {
  for (const auto& [key, value] : options_)
    if (key == name) return value;
  return std::nullopt;
}

int Args::intOption(const std::string& name, int fallback, int min, int max) const {
  const auto text = option(name);
  if (!text) return fallback;
  int value = 0;
  const auto [end, error] = std::from_chars(text->data(), text->data() + text->size(), value);
  if (error != std::errc() || end != text->data() + text->size() || value < min || value > max)
    throw UsageError("--" + name + " must be an integer in [" + std::to_string(min) + ", " +
                     std::to_string(max) + "], got '" + *text + "'");
  return value;
}

double Args::doubleOption(const std::string& name, double fallback) const {
  const auto text = option(name);
  if (!text) return fallback;
  try {
    size_t used = 0;
    const double value = std::stod(*text, &used);
    if (used == text->size() && std::isfinite(value)) return value;
  } catch (const std::exception&) {
  }
  throw UsageError("--" + name + " must be a number, got '" + *text + "'");
}

void Args::allowOnly(const std::set<std::string>& names) const {
  for (const auto& [key, value] : options_)
    if (!names.count(key)) throw UsageError("unknown option --" + key);
}

double meshToleranceOption(const Args& args, double fallback) {
  const double tolerance = args.doubleOption("mesh-tolerance", fallback);
  if (!(tolerance >= 0 && tolerance <= 0.5)) throw UsageError("--mesh-tolerance must be in [0, 0.5] (0: no refinement)");
  return tolerance;
}

}  // namespace penumbra::cli
