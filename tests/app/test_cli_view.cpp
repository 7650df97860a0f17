// `vascsim view` in a build without the viewer (the library alone: no GL package): the CLI says so in one
// line and exits with code 2, whatever follows the command.

#include <gtest/gtest.h>

#include <sstream>

#include "vascsim/app/cli.hpp"

namespace vascsim {
namespace {

TEST(CliView, WithoutTheViewerSaysSoInOneLineWithExitCode2) {
  std::ostringstream out, err;
  const int rc = run_cli(
      {"view", "scenes/realtime/hand-dorsal-vein-catheter.json", "--frames", "3", "--set", "model=xpbd"}, out,
      err);
  EXPECT_EQ(rc, 2);
  const std::string e = err.str();
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 1) << e;
  EXPECT_NE(e.find("built without the viewer"), std::string::npos) << e;
  EXPECT_NE(e.find("VASCSIM_BUILD_VIEWER=ON"), std::string::npos) << e;
  EXPECT_TRUE(out.str().empty());
}

}  // namespace
}  // namespace vascsim
