#pragma once
// The corner coordinates of an STL file, checked before assimp reads it: assimp's vertex joining merges a NaN
// corner into another vertex, so a file with NaN or infinite coordinates would be meshed silently.

#include <string>
#include <string_view>

namespace vascsim {

/// Throws InputError("<name>: STL: ...") if a corner coordinate of `bytes` (binary or ASCII STL) is not
/// finite.
void check_stl_numbers(std::string_view bytes, const std::string& name);

}  // namespace vascsim
