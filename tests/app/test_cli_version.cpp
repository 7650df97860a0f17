// `vascsim --version`: the version of CMakeLists.txt's project(VERSION ...) and the build configuration, exit
// code 0, whatever else is on the command line (it needs no subcommand).

#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>

#include "vascsim/app/cli.hpp"

namespace vascsim {
namespace {

std::string line_starting(const std::string& text, const std::string& key) {
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return line.substr(key.size());
  return "(missing)";
}

TEST(CliVersion, PrintsTheProjectVersionAndTheBuildConfiguration) {
  std::ostringstream out, err;
  ASSERT_EQ(run_cli({"--version"}, out, err), 0) << err.str();
  const std::string o = out.str();
  // The first line against the version CMake's project() declared, passed to this test separately.
  EXPECT_EQ(o.substr(0, o.find('\n')), std::string("vascsim ") + VASCSIM_PROJECT_VERSION) << o;
  EXPECT_EQ(line_starting(o, "build type: "), VASCSIM_CMAKE_BUILD_TYPE) << o;
  EXPECT_NE(line_starting(o, "compiler: "), "(missing)") << o;
  const std::string library = line_starting(o, "library: ");
  EXPECT_TRUE(library == "shared" || library == "static") << o;
  EXPECT_NE(line_starting(o, "OpenMP: "), "(missing)") << o;
  // libcholmod brings the BLAS in, so one is always loaded.
  EXPECT_NE(line_starting(o, "BLAS: ").find("libblas"), std::string::npos) << o;
  // This CLI is the library's alone (no viewer command registered).
  EXPECT_EQ(line_starting(o, "viewer: ").rfind("off", 0), 0u) << o;
  // A test binary of the build tree takes the bundled files from the source tree.
  EXPECT_TRUE(std::filesystem::equivalent(line_starting(o, "bundled files: "), VASCSIM_SOURCE_DIR)) << o;
  EXPECT_TRUE(err.str().empty()) << err.str();
}

TEST(CliVersion, WorksWithGlobalOptionsAndNeedsNoSubcommand) {
  std::ostringstream out, err;
  EXPECT_EQ(run_cli({"-q", "--version"}, out, err), 0) << err.str();
  EXPECT_EQ(out.str().rfind("vascsim ", 0), 0u) << out.str();
}

}  // namespace
}  // namespace vascsim
