#include "vascsim/io/obj_check.hpp"

#include <fmt/format.h>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <vector>

#include "vascsim/core/error.hpp"
#include "vascsim/core/text.hpp"

namespace vascsim {

namespace {

std::vector<std::string_view> obj_words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  const auto blank = [](char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; };
  while (i < line.size()) {
    while (i < line.size() && blank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !blank(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// A value as the message shows it: one line, at most 24 characters.
std::string shown_value(std::string_view value) {
  return one_line(value.size() > 24 ? std::string(value.substr(0, 24)) + "..." : std::string(value));
}

}  // namespace

void check_obj_vertices(std::string_view bytes, const std::string& name) {
  std::size_t line_no = 0, at = 0, vertex = 0;
  while (at < bytes.size()) {
    // One statement: a line, joined with the next ones while it ends in a backslash (OBJ's continuation,
    // which assimp follows). The message names the statement's first line.
    const std::size_t first_line = line_no + 1;
    std::string joined;
    std::string_view line;
    while (true) {
      std::size_t end = bytes.find('\n', at);
      if (end == std::string_view::npos) end = bytes.size();
      std::string_view part = bytes.substr(at, end - at);
      at = end + 1;
      ++line_no;
      while (!part.empty() && (part.back() == '\r' || part.back() == ' ' || part.back() == '\t'))
        part.remove_suffix(1);
      const bool continued = !part.empty() && part.back() == '\\' && at < bytes.size();
      if (continued) part.remove_suffix(1);
      if (!continued && joined.empty()) {
        line = part;
        break;
      }
      joined.append(part).push_back(' ');
      if (!continued) {
        line = joined;
        break;
      }
    }
    line = line.substr(0, line.find('#'));  // a comment
    const auto start = line.find_first_not_of(" \t\r\f\v");
    if (start == std::string_view::npos || line[start] != 'v') continue;
    const auto w = obj_words(line);
    if (w.empty() || w[0] != "v") continue;  // vn, vt, vp, f, ...: assimp's own checks
    ++vertex;
    const auto fail = [&](const std::string& why) {
      throw InputError(fmt::format("{}: OBJ: line {}: vertex {} {}", name, first_line, vertex, why));
    };
    const std::size_t values = w.size() - 1;
    if (values != 3 && values != 4 && values != 6)
      fail(fmt::format("has {} value{}; a vertex line holds x y z, x y z w or x y z r g b", values,
                       values == 1 ? "" : "s"));
    for (std::size_t k = 1; k < w.size(); ++k) {
      std::string_view text = w[k];
      if (text.size() > 1 && text[0] == '+' && text[1] != '-' && text[1] != '+') text.remove_prefix(1);
      // As long double, so that a number beyond a double (1e999) is read as what it is and one below it
      // (1e-400) as the zero it becomes; from_chars reads "nan" and "inf" as such.
      long double v = 0;
      const auto r = std::from_chars(text.data(), text.data() + text.size(), v);
      if (r.ec == std::errc::invalid_argument || r.ptr != text.data() + text.size())
        fail(fmt::format("has '{}', which is not a number", shown_value(w[k])));
      if (r.ec == std::errc::result_out_of_range || !std::isfinite(v) || std::fabs(v) > DBL_MAX)
        fail(
            fmt::format("has a non-finite value '{}' (NaN, infinite or beyond a double)", shown_value(w[k])));
      // assimp counts a value only when it starts with a digit or a sign: ".5" would shift the others.
      if (w[k][0] == '.')
        fail(fmt::format("has '{}': write a digit before the point (0{})", shown_value(w[k]),
                         shown_value(w[k])));
    }
  }
}

}  // namespace vascsim
