#include "server/json_error_path.h"

#include <nlohmann/json.hpp>
#include <vector>

namespace penumbra::server {

namespace {

using nlohmann::json;

// Follows the parse: one level per open array/object, the key or index being read in each.
class PathTracker : public nlohmann::json_sax<json> {
 public:
  std::string path() const {
    std::string out;
    for (const Level& level : levels_) {
      if (level.array)
        out += "[" + std::to_string(level.index) + "]";
      else if (level.hasKey)
        out += (out.empty() ? "" : ".") + level.key;
    }
    return out;
  }

  bool null() override { return value(); }
  bool boolean(bool) override { return value(); }
  bool number_integer(number_integer_t) override { return value(); }
  bool number_unsigned(number_unsigned_t) override { return value(); }
  bool number_float(number_float_t, const string_t&) override { return value(); }
  bool string(string_t&) override { return value(); }
  bool binary(binary_t&) override { return value(); }
  bool start_object(std::size_t) override { return open(false); }
  bool key(string_t& key) override {
    levels_.back().key = key;
    levels_.back().hasKey = true;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(true); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;
  }

 private:
  struct Level {
    bool array = false;
    size_t index = 0;  // arrays: the element being read
    bool hasKey = false;
    std::string key;  // objects: the key whose value is being read
  };
  bool open(bool array) {
    levels_.push_back({array, 0, false, {}});
    return true;
  }
  bool close() {
    levels_.pop_back();
    return value();
  }
  // A value ended: the enclosing array moves to its next element, the object to its next key.
  bool value() {
    if (levels_.empty()) return true;
    if (levels_.back().array)
      ++levels_.back().index;
    else
      levels_.back().hasKey = false;
    return true;
  }
  std::vector<Level> levels_;
};

}  // namespace

std::string jsonErrorPath(std::string_view text) {
  PathTracker tracker;
  if (json::sax_parse(text.begin(), text.end(), &tracker)) return "";
  return tracker.path();
}

}  // namespace penumbra::server
