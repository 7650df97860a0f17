// JSON parsing with bounded nesting and vascsim's own messages (core/json_file), and text that reaches the
// terminal kept on one printable line (core/text).

#include <gtest/gtest.h>

#include <string>

#include "vascsim/core/error.hpp"
#include "vascsim/core/json_file.hpp"
#include "vascsim/core/text.hpp"

namespace vascsim {
namespace {

std::string parse_error(const std::string& text) {
  try {
    parse_json_text(text, "f.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(JsonFile, NestingIsBoundedWhileParsing) {
  const auto nested = [](int depth) { return std::string(depth, '[') + std::string(depth, ']'); };
  EXPECT_EQ(parse_error(nested(kMaxJsonDepth)), "");
  EXPECT_EQ(parse_error(nested(kMaxJsonDepth + 1)),
            "f.json: arrays and objects nest deeper than 64 levels; a scene "
            "needs about 5");
  EXPECT_FALSE(try_parse_json(nested(200000)).has_value());
  EXPECT_EQ(try_parse_json("[1, 2]").value(), nlohmann::json({1, 2}));
}

TEST(JsonFile, MessagesAreVascsimsWithoutTheLibraryPrefix) {
  EXPECT_EQ(parse_error("{\"a\": }"),
            "f.json: not valid JSON: line 1, column 7: syntax error while parsing value - unexpected '}'; "
            "expected '[', "
            "'{', or a literal");
  EXPECT_EQ(parse_error("[1e999]"), "f.json: not valid JSON: number overflow parsing '1e999'");
  EXPECT_EQ(parse_error("// a comment\n{}"), "");
}

TEST(Text, Utf8Validity) {
  EXPECT_TRUE(is_valid_utf8("caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x98\x80"));
  EXPECT_FALSE(is_valid_utf8("caf\xE9"));       // Latin-1
  EXPECT_FALSE(is_valid_utf8("\xC0\xAF"));      // overlong '/'
  EXPECT_FALSE(is_valid_utf8("\xED\xA0\x80"));  // a surrogate
  EXPECT_FALSE(is_valid_utf8("\xE2\x82"));      // cut short
}

TEST(Text, OneLineEscapesControlsAndBadBytes) {
  EXPECT_EQ(one_line("a\nb\tc\r\x01 caf\xE9 \xC3\xA9"), "a\\nb\\tc\\r\\x01 caf\\xE9 \xC3\xA9");
}

}  // namespace
}  // namespace vascsim
