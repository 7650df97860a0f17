#pragma once
// Text checks for what reaches a user's terminal or a JSON file: valid UTF-8, one line.

#include <string>
#include <string_view>

namespace vascsim {

/// True when `s` is well-formed UTF-8 (what a JSON string must be).
bool is_valid_utf8(std::string_view s);

/// `s` on one printable line: newlines, tabs and other control characters as \n, \t, \xNN, and bytes that are
/// not well-formed UTF-8 as \xNN (an error message stays one line whatever the input held).
std::string one_line(std::string_view s);

}  // namespace vascsim
