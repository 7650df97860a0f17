#include "vascsim/interaction/device_csv.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <array>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <string_view>

#include "vascsim/core/error.hpp"

namespace vascsim::device_csv {

namespace {

constexpr std::string_view kLayout = "time_s,x_m,y_m,z_m[,qw,qx,qy,qz][,buttons][,fx_n,fy_n,fz_n]";
constexpr std::array<std::string_view, 4> kBase = {"time_s", "x_m", "y_m", "z_m"};
constexpr std::array<std::string_view, 4> kQuat = {"qw", "qx", "qy", "qz"};
constexpr std::array<std::string_view, 3> kForce = {"fx_n", "fy_n", "fz_n"};

std::string_view trim(std::string_view s) {
  // Spaces around cells and a CR from files written on Windows are tolerated.
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  const auto last = s.find_last_not_of(" \t\r");
  return s.substr(first, last - first + 1);
}

std::vector<std::string_view> split(std::string_view line) {
  std::vector<std::string_view> cells;
  std::size_t start = 0;
  while (true) {
    const auto comma = line.find(',', start);
    cells.push_back(
        trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  return cells;
}

/// True when `cells[at..]` starts with `group`; advances `at` past it.
template <std::size_t N>
bool take(const std::vector<std::string_view>& cells, std::size_t& at,
          const std::array<std::string_view, N>& group) {
  if (cells.size() < at + N) return false;
  for (std::size_t k = 0; k < N; ++k)
    if (cells[at + k] != group[k]) return false;
  at += N;
  return true;
}

/// The column names of a recognised header, in order.
std::vector<std::string> column_names(const Table& t) {
  std::vector<std::string> names(kBase.begin(), kBase.end());
  if (t.has_orientation) names.insert(names.end(), kQuat.begin(), kQuat.end());
  if (t.has_buttons) names.emplace_back("buttons");
  if (t.has_forces) names.insert(names.end(), kForce.begin(), kForce.end());
  return names;
}

}  // namespace

namespace {

// The header line: which optional column groups the file has. Returns false if it is not recognised.
bool parse_header(const std::vector<std::string_view>& cells, Table& t) {
  std::size_t at = 0;
  const bool ok = take(cells, at, kBase);
  t.has_orientation = ok && take(cells, at, kQuat);
  if (ok && at < cells.size() && cells[at] == "buttons") {
    t.has_buttons = true;
    ++at;
  }
  t.has_forces = ok && take(cells, at, kForce);
  return ok && at == cells.size();
}

// One data row into the table; `fail` throws naming the line.
template <class Fail>
void parse_row(const std::vector<std::string_view>& cells, const std::vector<std::string>& columns,
               int line_no, Table& t, const Fail& fail) {
  if (cells.size() != columns.size())
    fail(fmt::format("expected {} comma-separated values ({}), found {}", columns.size(),
                     fmt::join(columns, ","), cells.size()));
  std::array<double, 11> v{};  // every column except buttons, in header order
  std::uint32_t buttons = 0;
  std::size_t nv = 0;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    const std::string_view cell = cells[c];
    const char* end = cell.data() + cell.size();
    if (columns[c] == "buttons") {
      const auto r = std::from_chars(cell.data(), end, buttons);
      if (cell.empty() || r.ec != std::errc() || r.ptr != end)
        fail(fmt::format("column 'buttons': '{}' is not an integer in [0, {}] (a bit mask)", cell,
                         std::numeric_limits<std::uint32_t>::max()));
      continue;
    }
    double x = 0.0;
    const auto r = std::from_chars(cell.data(), end, x);
    if (cell.empty() || r.ec == std::errc::invalid_argument || r.ptr != end)
      fail(fmt::format("column '{}': '{}' is not a number; every value must be a finite decimal number",
                       columns[c], cell));
    if (r.ec == std::errc::result_out_of_range || !std::isfinite(x))
      fail(fmt::format("column '{}': value '{}' is not finite; NaN and infinite values are not allowed",
                       columns[c], cell));
    v[nv++] = x;
  }
  DevicePose p;
  p.time_s = v[0];
  p.position_m = Vec3(v[1], v[2], v[3]);
  std::size_t next = 4;
  if (t.has_orientation) {
    p.orientation = Eigen::Quaterniond(v[4], v[5], v[6], v[7]);  // Eigen's constructor order is w, x, y, z
    next = 8;
  }
  p.buttons = buttons;
  t.poses.push_back(p);
  t.lines.push_back(line_no);
  if (t.has_forces) t.forces_n.emplace_back(v[next], v[next + 1], v[next + 2]);
}

}  // namespace

Table read(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw InputError(
        fmt::format("{}: not a regular file (a folder, device or pipe); expected a CSV file with the "
                    "header {}",
                    name, kLayout));
  std::ifstream in(file);
  if (!in)
    throw InputError(fmt::format(
        "{}: cannot open the file (missing or unreadable); expected a CSV file with the header {}", name,
        kLayout));
  Table t;
  std::vector<std::string> columns;
  std::string line;
  int line_no = 0;
  const auto fail = [&](const std::string& what) {
    throw InputError(fmt::format("{}: line {}: {}", name, line_no, what));
  };
  while (std::getline(in, line)) {
    ++line_no;
    const std::string_view text = trim(line);
    // Blank lines and '#' comment lines carry no data (a recording may start with a comment).
    if (text.empty() || text.front() == '#') continue;
    const auto cells = split(text);
    if (!columns.empty()) {
      parse_row(cells, columns, line_no, t, fail);
      continue;
    }
    if (!parse_header(cells, t))
      fail(fmt::format("header '{}' is not recognised; expected {} (names in this order)", text, kLayout));
    columns = column_names(t);
  }
  if (in.bad()) throw InputError(fmt::format("{}: read error after line {}", name, line_no));
  if (columns.empty())
    throw InputError(
        fmt::format("{}: the file is empty (no header line); expected the header {}", name, kLayout));
  return t;
}

Trajectory to_trajectory(const Table& table, const std::filesystem::path& file) {
  const std::string name = file.string();
  return Trajectory(table.poses, name, [&](std::size_t i, std::string_view) {
    return fmt::format("{}: line {}", name, table.lines[i]);
  });
}

Writer::Writer(const std::filesystem::path& file, bool with_forces) : file_(file), with_forces_(with_forces) {
  out_ = std::fopen(file.c_str(), "w");
  if (!out_)
    throw InputError(fmt::format("{}: cannot write the file; check that its folder exists and is writable",
                                 file.string()));
  fmt::print(out_, "time_s,x_m,y_m,z_m,qw,qx,qy,qz,buttons{}\n", with_forces ? ",fx_n,fy_n,fz_n" : "");
}

Writer::~Writer() {
  if (out_) std::fclose(out_);
}

void Writer::row(const DevicePose& p, const Vec3* force_n) {
  // %.17g: 17 significant digits identify every double uniquely, so the file replays bit for bit.
  const auto& q = p.orientation;
  fmt::memory_buffer b;
  fmt::format_to(std::back_inserter(b), "{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g},{}",
                 p.time_s, p.position_m.x(), p.position_m.y(), p.position_m.z(), q.w(), q.x(), q.y(), q.z(),
                 p.buttons);
  if (with_forces_) {
    const Vec3 f = force_n ? *force_n : Vec3::Zero();
    fmt::format_to(std::back_inserter(b), ",{:.17g},{:.17g},{:.17g}", f.x(), f.y(), f.z());
  }
  b.push_back('\n');
  std::fwrite(b.data(), 1, b.size(), out_);
}

void Writer::close() {
  const bool failed = std::ferror(out_) != 0;
  const bool close_failed = std::fclose(out_) != 0;
  out_ = nullptr;
  if (failed || close_failed)
    throw InputError(fmt::format("{}: writing the file failed (disk full?)", file_.string()));
}

}  // namespace vascsim::device_csv
