#pragma once
// Files written at once (summary.json, a VTK frame, the .pvd index, a table written whole): the content goes
// to "<file>.tmp", is checked to the last byte (flush and close included), and only then renamed over <file>.
// A reader never sees half a file, and a failed write (disk full) is an InputError naming the file, never
// silent and never a crash.

#include <filesystem>
#include <string_view>

namespace vascsim {

/// Writes `content` to `file` through "<file>.tmp" and a rename. Throws InputError "<file>: cannot write:
/// ..." (the temporary file is removed).
void write_file_atomically(const std::filesystem::path& file, std::string_view content);

}  // namespace vascsim
