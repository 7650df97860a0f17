#pragma once
// Text checks for what reaches a user's terminal or a JSON file: valid UTF-8, one line; and the nearest of a
// set of names, for a message's "did you mean".

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace vascsim {

/// True when `s` is well-formed UTF-8 (what a JSON string must be).
bool is_valid_utf8(std::string_view s);

/// `s` on one printable line: newlines, tabs and other control characters as \n, \t, \xNN, and bytes that are
/// not well-formed UTF-8 as \xNN (an error message stays one line whatever the input held).
std::string one_line(std::string_view s);

/// Edits (insert, delete or replace a character, or swap two neighbours) that turn `a` into `b` (the optimal
/// string alignment distance: "wall_thicknes_m" is 1 from "wall_thickness_m", "c01_pa" 1 from "c10_pa").
std::size_t edit_distance(std::string_view a, std::string_view b);

/// The name of `names` nearest to `typed` when it is close enough to be a misspelling of it: at most 2 edits,
/// or a quarter of the name's length for a longer name, and fewer than half its characters (so a short name
/// is not offered for an unrelated one). Ties go to the first. None when nothing is that close.
std::optional<std::string> nearest_name(std::string_view typed, const std::vector<std::string>& names);

}  // namespace vascsim
