// ResourceLimitError: a per-scene size limit of the engine was reached (which limit,
// the value it would reach, the maximum). Immutable value; thread-safe.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace penumbra {

// Thrown as soon as a count would pass its limit (EngineSettings::limits), so a
// degenerate input fails fast instead of exhausting memory. Not a std::logic_error
// nor std::invalid_argument: no fallback path catches it as a geometric failure.
class ResourceLimitError : public std::runtime_error {
 public:
  // limit: the limit's name as documented ("faces", "tree_nodes", "vertices", "bytes").
  ResourceLimitError(std::string limit, size_t value, size_t maximum)
      : std::runtime_error("resource limit '" + limit + "' exceeded: " + std::to_string(value) + " > " +
                           std::to_string(maximum)),
        limit_(std::move(limit)),
        value_(value),
        maximum_(maximum) {}

  const std::string& limit() const { return limit_; }
  size_t value() const { return value_; }
  size_t maximum() const { return maximum_; }

 private:
  std::string limit_;
  size_t value_, maximum_;
};

}  // namespace penumbra
