// UTF-8 well-formedness for text that becomes JSON: checked where it enters (the server refuses
// it, 400 invalid_utf8) or, for names inside imported files, replaced. Stateless; thread-safe.
#pragma once

#include <string>
#include <string_view>

namespace penumbra::protocol {

// Whether `text` is well-formed UTF-8 (no overlong forms, surrogates or code points past U+10FFFF).
bool isValidUtf8(std::string_view text);

// `text` with every byte that does not start a well-formed sequence replaced by U+FFFD.
std::string replacingInvalidUtf8(std::string_view text);

}  // namespace penumbra::protocol
