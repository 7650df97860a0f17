#pragma once
// A structural check of a PLY file before assimp reads it. assimp's PLY loader trusts the header: a file
// without end_header makes it spin, a binary header over an ASCII body or a negative face index makes it read
// out of bounds, and a header that declares faces the body lacks trips an assertion. This walks the header
// and the whole body as declared (ASCII or binary, either byte order) and rejects such files with an
// InputError naming the element, item and property.

#include <string>
#include <string_view>

namespace vascsim {

/// Throws InputError("<name>: ...") unless `bytes` is a complete PLY file: a header ending in end_header,
/// every element's items present with the declared properties, finite numbers, and face vertex indices in
/// [0, number of vertices).
void check_ply(std::string_view bytes, const std::string& name);

}  // namespace vascsim
