#pragma once
// The vertex lines of an OBJ file, checked before assimp reads them. assimp's OBJ reader takes what it can
// read of a number and goes on: "nan" and "inf" become NaN and infinity (a vertex no face uses is then
// dropped, so the file is meshed silently), "1,5" becomes 1 and "0x1" 0, and a line of two numbers ends in a
// message about face indices. This reads every "v" line itself and names the file and the line.

#include <string>
#include <string_view>

namespace vascsim {

/// Throws InputError("<name>: OBJ: line <n>: ...") unless every vertex line of `bytes` ("v x y z", optionally
/// with w, or with r g b as many exporters write) holds 3, 4 or 6 values, each a finite number.
void check_obj_vertices(std::string_view bytes, const std::string& name);

}  // namespace vascsim
