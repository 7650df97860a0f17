// What the command line prints on stderr: with -q only warnings and errors (no log lines, no progress), and a
// progress line never above 100 % (a realtime session runs a few ticks past its nominal end).

#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include "support/cli_capture.hpp"
#include "support/run_helpers.hpp"
#include "vascsim/app/progress.hpp"

namespace vascsim {
namespace {

// A progress line of app/progress.cpp when stderr is not a terminal: "<label>: done/total (percent%) ...".
const std::regex kProgressLine(R"((^|\n)\S+: \d+/\d+ \(\d+%\) )");

TEST(CliQuiet, QuietPrintsNoProgressAndNoInformation) {
  const auto dir = test::fresh_test_dir();
  const auto quiet = test::run_cli_captured(
      {"-q", "run", test::source_path("scenes/cantilever.json"), "--out", (dir / "q").string(), "--yes"});
  ASSERT_EQ(quiet.code, 0) << quiet.err;
  EXPECT_FALSE(std::regex_search(quiet.err, kProgressLine)) << quiet.err;
  EXPECT_FALSE(quiet.err_has("[info]")) << quiet.err;
  EXPECT_TRUE(quiet.out_has("tip deflection")) << quiet.out;  // the result still goes to stdout
  // Without -q the same run shows its progress (so the check above can fail).
  const auto loud = test::run_cli_captured(
      {"run", test::source_path("scenes/cantilever.json"), "--out", (dir / "l").string(), "--yes"});
  ASSERT_EQ(loud.code, 0) << loud.err;
  EXPECT_TRUE(std::regex_search(loud.err, kProgressLine)) << loud.err;
}

TEST(CliQuiet, ProgressNeverShowsMoreThanTheWhole) {
  std::ostringstream out;
  Progress p(out, false, "session");
  p.update(1043, 1000, "t = 2.19 s");
  EXPECT_NE(out.str().find("session: 1000/1000 (100%)"), std::string::npos) << out.str();
  std::ostringstream none;
  Progress q(none, false, "session", true);
  q.update(500, 1000, "half");
  q.finish();
  EXPECT_TRUE(none.str().empty()) << none.str();
}

// A realtime session's last lines say what the hand got beside the model: how old the frames its force came
// from were, how far the model's tool stayed behind, and the largest force sent to the hand beside the
// model's own.
TEST(CliQuiet, ARealtimeSessionSaysWhatTheHandGotRealtime) {
  const auto dir = test::fresh_test_dir();
  const auto r = test::run_cli_captured({"-q", "run", test::source_path("tests/data/haptic-block.json"),
                                         "--set", test::kCoarseHapticBlock[0], "--mode", "realtime", "--out",
                                         (dir / "rt").string()});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(r.out_has("the hand: the force it felt came from frames")) << r.out;
  EXPECT_TRUE(r.out_has("the model's tool stayed at most")) << r.out;
  EXPECT_TRUE(r.out_has("force sent to the hand at most")) << r.out;
}

}  // namespace
}  // namespace vascsim
