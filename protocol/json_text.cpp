#include "protocol/json_text.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "protocol/validation_error.h"

namespace penumbra::protocol {

namespace {

// nlohmann prefixes messages with "[json.exception.parse_error.101] "; the
// reader of our message does not need the library's error id.
std::string withoutLibraryPrefix(const char* what) {
  std::string message = what;
  if (!message.empty() && message.front() == '[') {
    const size_t end = message.find("] ");
    if (end != std::string::npos) message.erase(0, end + 2);
  }
  return message;
}

// Nesting depth is checked on the raw text before parsing, so a hostile
// document is refused before any tree is built. Brackets inside strings do not
// count; malformed text may be miscounted, but the parser refuses it anyway.
void checkDepth(std::string_view text, int maxDepth) {
  int depth = 0;
  bool inString = false, escaped = false;
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (inString) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') inString = false;
      continue;
    }
    if (c == '"') {
      inString = true;
    } else if (c == '[' || c == '{') {
      if (++depth > maxDepth)
        throw ValidationError(kJsonTextPath, "JSON nests deeper than the limit of " +
                                                 std::to_string(maxDepth) + " levels (at byte " +
                                                 std::to_string(i) + ")");
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
}

}  // namespace

nlohmann::json parseJsonText(std::string_view text, size_t maxBytes, int maxDepth) {
  if (text.size() > maxBytes)
    throw ValidationError(kJsonTextPath, "input is " + std::to_string(text.size()) +
                                             " bytes, over the limit of " + std::to_string(maxBytes) +
                                             " bytes");
  checkDepth(text, maxDepth);
  try {
    return nlohmann::json::parse(text.data(), text.data() + text.size());
  } catch (const nlohmann::json::parse_error& e) {
    throw ValidationError(kJsonTextPath, "invalid JSON at byte " + std::to_string(e.byte) + ": " +
                                             withoutLibraryPrefix(e.what()));
  } catch (const nlohmann::json::exception& e) {
    // e.g. out_of_range 406: a number like 1e400 overflows a double.
    throw ValidationError(kJsonTextPath, "invalid JSON: " + withoutLibraryPrefix(e.what()));
  }
}

std::string readTextFile(const std::string& path, size_t maxBytes) {
  std::error_code error;
  const auto size = std::filesystem::file_size(path, error);
  if (error) throw std::runtime_error("cannot read '" + path + "': " + error.message());
  if (size > maxBytes)
    throw ValidationError(kJsonTextPath, "file '" + path + "' is " + std::to_string(size) +
                                             " bytes, over the limit of " + std::to_string(maxBytes) +
                                             " bytes");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error("cannot open '" + path + "': " + std::strerror(errno));
  std::string text(size, '\0');
  in.read(text.data(), std::streamsize(size));
  // The file may have changed size since file_size(); keep what was read.
  text.resize(size_t(in.gcount()));
  if (in.bad()) throw std::runtime_error("cannot read '" + path + "'");
  return text;
}

void writeTextFile(const std::string& path, std::string_view text) {
  writeTextFileWith(path, [&](std::ostream& out) { out.write(text.data(), std::streamsize(text.size())); });
}

void writeTextFileWith(const std::string& path, const std::function<void(std::ostream&)>& write) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error("cannot open '" + path + "' for writing: " + std::strerror(errno));
  write(out);
  out.close();
  if (!out) throw std::runtime_error("cannot write '" + path + "'");
}

}  // namespace penumbra::protocol
