#include "vascsim/core/json_file.hpp"

#include <fmt/format.h>
#include <fstream>
#include <sstream>

#include "vascsim/core/error.hpp"

namespace vascsim {

namespace {

constexpr std::uintmax_t kMaxJsonFileBytes = 256u << 20;

struct TooDeep {};

// Stops the parser at the first value nested deeper than kMaxJsonDepth (the callback sees every depth).
const nlohmann::json::parser_callback_t depth_limit = [](int depth, nlohmann::json::parse_event_t,
                                                         nlohmann::json&) {
  if (depth >= kMaxJsonDepth) throw TooDeep{};  // depth counts from 0 at the outermost value
  return true;
};

// nlohmann's text without its "[json.exception.parse_error.101] parse error at " prefix.
std::string library_reason(const nlohmann::json::exception& e) {
  std::string what = e.what();
  const auto close = what.find("] ");
  if (what.rfind("[json.exception.", 0) == 0 && close != std::string::npos) what.erase(0, close + 2);
  if (what.rfind("parse error at ", 0) == 0) what.erase(0, 15);
  return what;
}

nlohmann::json parse(const std::string& text) {
  return nlohmann::json::parse(text, depth_limit, /*allow_exceptions=*/true, /*ignore_comments=*/true);
}

}  // namespace

nlohmann::json parse_json_text(const std::string& text, const std::string& file) {
  try {
    return parse(text);
  } catch (const TooDeep&) {
    throw InputError(fmt::format("{}: arrays and objects nest deeper than {} levels; a scene needs about 5",
                                 file, kMaxJsonDepth));
  } catch (const nlohmann::json::exception& e) {
    // parse errors, and out_of_range for a number beyond a double (1e999)
    throw InputError(fmt::format("{}: not valid JSON: {}", file, library_reason(e)));
  }
}

std::optional<nlohmann::json> try_parse_json(const std::string& text) {
  try {
    return parse(text);
  } catch (const TooDeep&) {
  } catch (const nlohmann::json::exception&) {
  }
  return std::nullopt;
}

nlohmann::json read_json_file(const std::filesystem::path& file, const std::string& noun,
                              const std::string& expected) {
  const std::string name = file.string();
  std::error_code ec;
  if (std::filesystem::is_directory(file, ec))
    throw InputError(fmt::format("{}: is a folder, not a file; {}", name, expected));
  if (std::filesystem::exists(file, ec) && !std::filesystem::is_regular_file(file, ec))
    throw InputError(fmt::format("{}: is not a regular file (a device or pipe); {}", name, expected));
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > kMaxJsonFileBytes)
    throw InputError(
        fmt::format("{}: {} bytes; a JSON input may have at most {} bytes", name, size, kMaxJsonFileBytes));
  std::ifstream in(file, std::ios::binary);
  if (!in)
    throw InputError(fmt::format("{}: cannot open {} (missing or unreadable); {}", name, noun, expected));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw InputError(fmt::format("{}: read error; {}", name, expected));
  return parse_json_text(text.str(), name);
}

}  // namespace vascsim
