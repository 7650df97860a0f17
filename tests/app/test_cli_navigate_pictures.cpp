// `vascsim navigate --pictures` in a build without the viewer (the library alone: no GL package): the CLI
// says so in one line and exits with code 2 before the run, which may take minutes.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <sstream>

#include "support/run_helpers.hpp"
#include "vascsim/app/cli.hpp"

namespace vascsim {
namespace {

TEST(CliNavigatePictures, WithoutTheViewerSaysSoInOneLineBeforeTheRun) {
  const std::filesystem::path out_dir =
      std::filesystem::temp_directory_path() / "vascsim-navigate-pictures-without-viewer";
  std::filesystem::remove_all(out_dir);
  std::ostringstream out, err;
  const int rc = run_cli({"navigate", test::source_path("scenes/navigation/aorta-bent-guidewire.json"),
                          "--out", out_dir.string(), "--pictures"},
                         out, err);
  EXPECT_EQ(rc, 2);
  const std::string e = err.str();
  EXPECT_EQ(std::count(e.begin(), e.end(), '\n'), 1) << e;
  EXPECT_NE(e.find("--pictures: this vascsim was built without the viewer"), std::string::npos) << e;
  EXPECT_NE(e.find("VASCSIM_BUILD_VIEWER=ON"), std::string::npos) << e;
  EXPECT_TRUE(out.str().empty());
  EXPECT_FALSE(std::filesystem::exists(out_dir / "instrument.csv"));  // nothing ran
}

}  // namespace
}  // namespace vascsim
