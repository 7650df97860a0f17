#include "vascsim/io/ply_check.hpp"

#include <fmt/format.h>
#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

constexpr std::size_t kMaxHeaderBytes = 1 << 20;
constexpr double kMaxItems = 1e9;

enum class Format { ascii, binary_le, binary_be };

struct Type {
  int bytes = 0;  // 0: not a PLY type
  bool is_float = false, is_signed = false;
};

Type type_of(std::string_view t) {
  if (t == "char" || t == "int8") return {1, false, true};
  if (t == "uchar" || t == "uint8") return {1, false, false};
  if (t == "short" || t == "int16") return {2, false, true};
  if (t == "ushort" || t == "uint16") return {2, false, false};
  if (t == "int" || t == "int32") return {4, false, true};
  if (t == "uint" || t == "uint32") return {4, false, false};
  if (t == "float" || t == "float32") return {4, true, true};
  if (t == "double" || t == "float64") return {8, true, true};
  return {};
}

struct Property {
  std::string name;
  Type type;        // the value, or a list's items
  Type count_type;  // a list's count (bytes 0: not a list)
  bool is_list() const { return count_type.bytes > 0; }
};

struct Element {
  std::string name;
  double count = 0;
  std::vector<Property> properties;
};

std::vector<std::string_view> words(std::string_view line) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t' || line[i] == '\r')) ++i;
    const std::size_t start = i;
    while (i < line.size() && line[i] != ' ' && line[i] != '\t' && line[i] != '\r') ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
  return out;
}

// Reads header lines up to end_header; returns the offset of the body.
class PlyChecker {
 public:
  PlyChecker(std::string_view bytes, const std::string& name) : bytes_(bytes), name_(name) {}

  void run() {
    const std::size_t body = read_header();
    if (format_ == Format::ascii)
      walk_ascii(body);
    else
      walk_binary(body);
  }

 private:
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(fmt::format("{}: PLY: {}", name_, why));
  }

  std::string where(const Element& e, double item, const Property& p) const {
    return fmt::format("element '{}' item {} property '{}'", e.name, static_cast<long long>(item), p.name);
  }

  std::size_t read_header();
  void header_line(const std::vector<std::string_view>& w, int line_no);
  void walk_binary(std::size_t at);
  void walk_ascii(std::size_t at);
  void check_value(double v, const Element& e, double item, const Property& p, bool list_item) const;
  void check_list_size(double n, const Element& e, double item, const Property& p) const;
  static bool is_face_indices(const Element& e, const Property& p) {
    return e.name == "face" && (p.name == "vertex_indices" || p.name == "vertex_index");
  }

  std::string_view bytes_;
  const std::string& name_;
  Format format_ = Format::ascii;
  bool have_format_ = false;
  std::vector<Element> elements_;
  double vertices_ = 0;
};

std::size_t PlyChecker::read_header() {
  std::size_t at = 0;
  int line_no = 0;
  while (true) {
    const std::size_t end = bytes_.find('\n', at);
    if (end == std::string_view::npos || end > kMaxHeaderBytes)
      fail(fmt::format("no 'end_header' line in the first {} bytes (not a complete PLY header)",
                       std::min(bytes_.size(), kMaxHeaderBytes)));
    const auto w = words(bytes_.substr(at, end - at));
    ++line_no;
    at = end + 1;
    if (line_no == 1) {
      if (w.size() != 1 || w[0] != "ply") fail("the file does not start with a 'ply' line");
      continue;
    }
    if (!w.empty() && w[0] == "end_header") break;
    header_line(w, line_no);
  }
  if (!have_format_) fail("the header has no 'format' line");
  // The vertex element must carry x, y and z as numbers (assimp takes the positions from them).
  for (const Element& e : elements_) {
    if (e.name != "vertex") continue;
    for (const char* axis : {"x", "y", "z"})
      if (std::none_of(e.properties.begin(), e.properties.end(),
                       [&](const Property& p) { return p.name == axis && !p.is_list(); }))
        fail(fmt::format("element 'vertex' has no property '{}'", axis));
  }
  for (const Element& e : elements_)
    if (e.name == "vertex") vertices_ = e.count;
  return at;
}

void PlyChecker::header_line(const std::vector<std::string_view>& w, int line_no) {
  const auto bad = [&](const std::string& why) { fail(fmt::format("header line {}: {}", line_no, why)); };
  if (w.empty() || w[0] == "comment" || w[0] == "obj_info") return;
  if (w[0] == "format") {
    if (have_format_) bad("a second 'format' line");
    if (w.size() != 3) bad("expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
    if (w[1] == "ascii")
      format_ = Format::ascii;
    else if (w[1] == "binary_little_endian")
      format_ = Format::binary_le;
    else if (w[1] == "binary_big_endian")
      format_ = Format::binary_be;
    else
      bad(fmt::format("unknown format '{}'", w[1]));
    have_format_ = true;
  } else if (w[0] == "element") {
    double count = -1;
    if (w.size() == 3) std::from_chars(w[2].data(), w[2].data() + w[2].size(), count);
    if (!(count >= 0 && count <= kMaxItems && std::floor(count) == count))
      bad(fmt::format("expected 'element <name> <count>' with a count in [0, {:.0e}]", kMaxItems));
    for (const Element& e : elements_)
      if (e.name == w[1]) bad(fmt::format("a second element '{}'", w[1]));
    elements_.push_back({std::string(w[1]), count, {}});
  } else if (w[0] == "property") {
    if (elements_.empty()) bad("a property before any element");
    Property p;
    if (w.size() == 3) {
      p.type = type_of(w[1]);
      p.name = w[2];
    } else if (w.size() == 5 && w[1] == "list") {
      p.count_type = type_of(w[2]);
      p.type = type_of(w[3]);
      p.name = w[4];
      if (p.count_type.bytes == 0 || p.count_type.is_float)
        bad("a list's count type must be an integer type");
    } else {
      bad("expected 'property <type> <name>' or 'property list <count type> <item type> <name>'");
    }
    if (p.type.bytes == 0) bad("unknown property type");
    for (const char c : p.name)
      if (!(std::isalnum(static_cast<unsigned char>(c)) || c == '_'))
        bad("a property name must be letters, digits or '_'");
    // assimp reads a face's vertices from its list property named vertex_indices (or vertex_index): any other
    // list on a face would be indices this check does not bound.
    if (elements_.back().name == "face" && p.is_list() && p.name != "vertex_indices" &&
        p.name != "vertex_index")
      bad(fmt::format("the face list '{}' is not 'vertex_indices'", p.name));
    elements_.back().properties.push_back(p);
  } else {
    bad(fmt::format("'{}' is not a PLY header keyword", w[0]));
  }
}

// Every number in the body: finite, an integer where the type is, a face's vertex index in range.
void PlyChecker::check_value(double v, const Element& e, double item, const Property& p,
                             bool list_item) const {
  if (!std::isfinite(v)) fail(fmt::format("{}: the value is not finite", where(e, item, p)));
  if (!p.type.is_float && std::floor(v) != v)
    fail(fmt::format("{}: {} is not an integer", where(e, item, p), v));
  if (list_item && is_face_indices(e, p) && !(v >= 0 && v < vertices_))
    fail(fmt::format("{}: vertex index {} is outside [0, {}) (the file has {} vertices)", where(e, item, p),
                     v, vertices_, vertices_));
}

// A list's length: a whole number >= 0; a face's vertex list at least 3 (assimp's triangulation asserts on
// faces of fewer).
void PlyChecker::check_list_size(double n, const Element& e, double item, const Property& p) const {
  if (!(n >= 0 && std::floor(n) == n)) fail(fmt::format("{}: a list of {} items", where(e, item, p), n));
  if (is_face_indices(e, p) && n < 3)
    fail(fmt::format("{}: a face of {} vertices; a face needs at least 3", where(e, item, p), n));
}

double read_binary(const char* p, const Type& t, bool big_endian) {
  unsigned char b[8];
  std::memcpy(b, p, static_cast<std::size_t>(t.bytes));
  if (big_endian != (std::endian::native == std::endian::big)) std::reverse(b, b + t.bytes);
  switch (t.bytes) {
    case 1:
      return t.is_signed ? static_cast<double>(std::bit_cast<std::int8_t>(b[0])) : b[0];
    case 2: {
      std::uint16_t u;
      std::memcpy(&u, b, 2);
      return t.is_signed ? static_cast<double>(static_cast<std::int16_t>(u)) : u;
    }
    case 4: {
      std::uint32_t u;
      std::memcpy(&u, b, 4);
      if (t.is_float) return std::bit_cast<float>(u);
      return t.is_signed ? static_cast<double>(static_cast<std::int32_t>(u)) : u;
    }
    default: {
      double d;
      std::memcpy(&d, b, 8);
      return d;
    }
  }
}

void PlyChecker::walk_binary(std::size_t at) {
  const bool big = format_ == Format::binary_be;
  const auto take = [&](const Type& t, const Element& e, double item, const Property& p) {
    if (bytes_.size() - at < static_cast<std::size_t>(t.bytes))
      fail(fmt::format(
          "{}: the body ends here ({} elements declared; truncated, or an ASCII body under a binary "
          "header)",
          where(e, item, p), e.count));
    const double v = read_binary(bytes_.data() + at, t, big);
    at += static_cast<std::size_t>(t.bytes);
    return v;
  };
  for (const Element& e : elements_) {
    if (e.properties.empty()) continue;  // items of no bytes
    for (double item = 0; item < e.count; ++item)
      for (const Property& p : e.properties) {
        if (!p.is_list()) {
          check_value(take(p.type, e, item, p), e, item, p, false);
          continue;
        }
        const double n = take(p.count_type, e, item, p);
        check_list_size(n, e, item, p);
        for (double k = 0; k < n; ++k) check_value(take(p.type, e, item, p), e, item, p, true);
      }
  }
}

void PlyChecker::walk_ascii(std::size_t at) {
  int line_no = 0;
  for (const Element& e : elements_)
    for (double item = 0; item < e.count; ++item) {
      const auto fail_item = [&](const std::string& why) {
        fail(fmt::format("element '{}' item {} (body line {}): {}", e.name, static_cast<long long>(item),
                         line_no, why));
      };
      if (at >= bytes_.size())
        fail(fmt::format("element '{}': {} items declared, the body ends after {}", e.name, e.count,
                         static_cast<long long>(item)));
      std::size_t end = bytes_.find('\n', at);
      if (end == std::string_view::npos) end = bytes_.size();
      const auto w = words(bytes_.substr(at, end - at));
      at = end + 1;
      ++line_no;
      std::size_t next = 0;
      const auto number = [&](const Property& p) {
        if (next >= w.size()) fail_item(fmt::format("property '{}': missing value", p.name));
        double v = 0;
        const auto r = std::from_chars(w[next].data(), w[next].data() + w[next].size(), v);
        if (r.ec != std::errc() || r.ptr != w[next].data() + w[next].size())
          fail_item(fmt::format("property '{}': '{}' is not a number", p.name, w[next]));
        ++next;
        return v;
      };
      for (const Property& p : e.properties) {
        if (!p.is_list()) {
          check_value(number(p), e, item, p, false);
          continue;
        }
        const double n = number(p);
        check_list_size(n, e, item, p);
        for (double k = 0; k < n; ++k) check_value(number(p), e, item, p, true);
      }
      if (next != w.size()) fail_item(fmt::format("{} values where the header declares {}", w.size(), next));
    }
}

}  // namespace

void check_ply(std::string_view bytes, const std::string& name) {
  PlyChecker(bytes, name).run();
}

}  // namespace vascsim
