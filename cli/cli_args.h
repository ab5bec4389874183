// Command-line arguments of one `penumbra` subcommand: positionals and --options.
// Plain value built once from argv; not shared between threads.
#pragma once

#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace penumbra::cli {

// A usage error: exit status 2 with the message and the command's usage.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // `flags` take no value; every other --name takes the next argument.
  Args(int argc, char** argv, int first, std::set<std::string> flags);

  const std::vector<std::string>& positionals() const { return positionals_; }
  std::string positional(size_t index, const char* what) const;
  bool flag(const std::string& name) const { return flags_.count(name) > 0; }
  std::optional<std::string> option(const std::string& name) const;
  int intOption(const std::string& name, int fallback, int min, int max) const;
  double doubleOption(const std::string& name, double fallback) const;
  // Refuses options the command does not know.
  void allowOnly(const std::set<std::string>& names) const;

 private:
  std::vector<std::string> positionals_;
  std::set<std::string> flags_;
  std::vector<std::pair<std::string, std::string>> options_;
};

}  // namespace penumbra::cli
