// ValidationError: input that breaks the JSON contract, with the key path of the
// offending value (e.g. `objects[3].faces[7]`). Immutable value; thread-safe.
#pragma once

#include <stdexcept>
#include <string>

namespace penumbra::protocol {

// Path of errors in the raw text itself (size, depth, syntax), not in a value.
inline constexpr const char* kJsonTextPath = "(json)";

class ValidationError : public std::invalid_argument {
 public:
  // path: key path of the bad value ("" for the document root).
  // what() is "path: problem", or just "problem" at the root.
  ValidationError(std::string path, std::string problem)
      : std::invalid_argument(path.empty() ? problem : path + ": " + problem),
        path_(std::move(path)),
        problem_(std::move(problem)) {}

  const std::string& path() const { return path_; }
  const std::string& problem() const { return problem_; }

 private:
  std::string path_;
  std::string problem_;
};

}  // namespace penumbra::protocol
