#include "vascsim/io/stl_check.hpp"

#include <fmt/format.h>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

// Binary STL: an 80-byte header, a 32-bit triangle count, 50 bytes per triangle (normal, three corners as
// little-endian floats, a 16-bit attribute). assimp takes a file of exactly that size as binary.
bool is_binary(std::string_view b) {
  if (b.size() < 84) return false;
  std::uint32_t count = 0;
  std::memcpy(&count, b.data() + 80, 4);
  return b.size() == 84 + 50 * static_cast<std::uint64_t>(count);
}

}  // namespace

void check_stl_numbers(std::string_view bytes, const std::string& name) {
  const auto fail = [&](const std::string& where) {
    throw InputError(
        fmt::format("{}: STL: {} has a non-finite coordinate (NaN or infinite) at a corner", name, where));
  };
  if (is_binary(bytes)) {
    const std::size_t count = (bytes.size() - 84) / 50;
    for (std::size_t t = 0; t < count; ++t)
      for (int c = 3; c < 12; ++c) {  // skip the normal (3 floats): assimp recomputes it
        float v;
        std::memcpy(&v, bytes.data() + 84 + 50 * t + 4 * static_cast<std::size_t>(c), 4);
        if (!std::isfinite(v)) fail(fmt::format("triangle {}", t));
      }
    return;
  }
  // ASCII: every "vertex x y z" line.
  std::size_t line_no = 0, at = 0;
  while (at < bytes.size()) {
    std::size_t end = bytes.find('\n', at);
    if (end == std::string_view::npos) end = bytes.size();
    std::string_view line = bytes.substr(at, end - at);
    at = end + 1;
    ++line_no;
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || line.substr(first, 6) != "vertex") continue;
    line.remove_prefix(first + 6);
    for (int k = 0; k < 3; ++k) {
      const auto start = line.find_first_not_of(" \t\r");
      if (start == std::string_view::npos) break;
      line.remove_prefix(start);
      double v = 0.0;
      const auto r = std::from_chars(line.data(), line.data() + line.size(), v);
      // from_chars reads "nan" and "inf" as such; a number beyond a double is out of range.
      if (r.ec == std::errc::result_out_of_range || (r.ec == std::errc() && !std::isfinite(v)))
        fail(fmt::format("line {}", line_no));
      line.remove_prefix(static_cast<std::size_t>(r.ptr - line.data()));
    }
  }
}

}  // namespace vascsim
