// Where the bundled scenes, data and scripts are found (core/bundled_files.hpp): the source tree for this
// build-tree library, $VASCSIM_DATA_DIR first when set, and a file missing everywhere named under the root in
// use. The installed layout (share/vascsim next to the installed library) is checked by the install test
// (tests/install/check_install.sh).

#include <gtest/gtest.h>

#include <unistd.h>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "vascsim/core/bundled_files.hpp"

namespace vascsim {
namespace {

namespace fs = std::filesystem;

// Sets an environment variable for the enclosing scope and restores it.
class ScopedEnv {
 public:
  ScopedEnv(const char* name, const std::string& value) : name_(name) {
    if (const char* old = std::getenv(name)) old_ = old, had_ = true;
    setenv(name, value.c_str(), 1);
  }
  ~ScopedEnv() {
    if (had_)
      setenv(name_, old_.c_str(), 1);
    else
      unsetenv(name_);
  }

 private:
  const char* name_;
  std::string old_;
  bool had_ = false;
};

TEST(BundledFiles, TheBuildTreeReadsTheSourceTree) {
  if (std::getenv("VASCSIM_DATA_DIR")) GTEST_SKIP() << "VASCSIM_DATA_DIR is set";
  EXPECT_TRUE(fs::equivalent(bundled_root(), VASCSIM_SOURCE_DIR));
  const fs::path script = bundled_file("scripts/plot_force_displacement.py");
  EXPECT_TRUE(fs::equivalent(script, fs::path(VASCSIM_SOURCE_DIR) / "scripts/plot_force_displacement.py"))
      << script;
  EXPECT_TRUE(fs::is_directory(bundled_file("data/ahp")));
}

TEST(BundledFiles, TheEnvironmentComesFirstAndMissingFilesFallThrough) {
  const fs::path dir = fs::temp_directory_path() / ("vascsim-bundled-files-" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "scripts");
  fs::create_directories(dir / "scenes");
  std::ofstream(dir / "scripts" / "plot_force_displacement.py") << "# a stand-in\n";
  {
    ScopedEnv env("VASCSIM_DATA_DIR", dir.string());
    EXPECT_EQ(bundled_roots().front(), dir);
    EXPECT_EQ(bundled_root(), dir);
    EXPECT_EQ(bundled_file("scripts/plot_force_displacement.py"), dir / "scripts/plot_force_displacement.py");
    // Not in the override: the next root that has it (the source tree here).
    EXPECT_TRUE(fs::equivalent(bundled_file("scripts/plot_ahp.py"),
                               fs::path(VASCSIM_SOURCE_DIR) / "scripts/plot_ahp.py"));
    // Nowhere: named under the root in use, so a message points where the user would look.
    EXPECT_EQ(bundled_file("scripts/no-such-script.py"), dir / "scripts/no-such-script.py");
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace vascsim
