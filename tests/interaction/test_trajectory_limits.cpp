// Device files from the hostile-input reproducers (docs/reliability.md): a quaternion too large to square,
// recordings that are devices or folders, and JSON trajectories nested without bound.

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/cli_capture.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/interaction/session_recording.hpp"
#include "vascsim/interaction/trajectory.hpp"

namespace vascsim {
namespace {

TEST(TrajectoryLimits, HugeQuaternionNormalisesWithoutOverflow) {
  DevicePose p;
  p.orientation = Eigen::Quaterniond(1e300, 1e300, 0.0, 0.0);  // w, x, y, z: |q|^2 overflows a double
  const Trajectory t({p});
  const auto& q = t.samples()[0].orientation;
  // 1e-15: two divisions and a square root of exactly representable ratios.
  EXPECT_NEAR(q.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.x(), std::sqrt(0.5), 1e-15);
  EXPECT_EQ(q.y(), 0.0);
  EXPECT_EQ(q.z(), 0.0);
}

TEST(TrajectoryLimits, RecordingThatIsNotARegularFileIsAnInputError) {
  for (const char* file : {"/dev/zero", "/tmp"}) {
    try {
      read_session_recording(file);
      ADD_FAILURE() << file << " was read";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
  }
}

TEST(TrajectoryLimits, DeeplyNestedJsonTrajectoryIsAnInputError) {
  const auto file = test::fresh_test_dir() / "deep.json";
  test::write_file(file, R"({"samples": )" + std::string(100000, '[') + std::string(100000, ']') + "}");
  try {
    read_trajectory(file);
    ADD_FAILURE() << "read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nest deeper than 64"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace vascsim
