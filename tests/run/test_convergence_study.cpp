// `vascsim converge` (run/convergence_study.hpp): on the cantilever, whose CalculiX reference is converged to
// 0.2 %, the estimate's bound must contain the scene's true error; a sequence that goes up and down gives no
// number; two lattices whose nodes fall differently under the tool do not count as one family.

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "support/cli_capture.hpp"
#include "support/run_helpers.hpp"
#include "vascsim/run/convergence_study.hpp"
#include "vascsim/run/runner.hpp"

namespace vascsim {
namespace {

// The CalculiX reference of validation/references/cantilever.csv: (tip deflection, its uncertainty), m.
std::pair<double, double> cantilever_reference() {
  std::ifstream in(test::source_path("validation/references/cantilever.csv"));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  std::stringstream cells(row);
  std::string step, load, deflection, uncertainty;
  std::getline(cells, step, ',');
  std::getline(cells, load, ',');
  std::getline(cells, deflection, ',');
  std::getline(cells, uncertainty, ',');
  return {std::stod(deflection), std::stod(uncertainty)};
}

// The scene's 2.5 mm beam between 1.25 and 5 mm (ratio 2: whole cells across the 10 mm section at every
// level). The bound must contain the error against CalculiX; the reference's own uncertainty (0.22 %) is
// added to the bound, as the two are independent estimates of the same continuum.
TEST(ConvergenceStudy, TheCantileverBoundContainsItsErrorAgainstCalculix) {
  const auto dir = test::fresh_test_dir();
  ConvergenceOptions options;
  options.out_dir = dir;
  options.ratio = 2.0;
  options.coarser_levels = 1;
  options.finer = true;
  const ConvergenceResult r =
      run_convergence_study(load_scene(test::source_path("scenes/cantilever.json")), options);
  ASSERT_TRUE(r.refused.empty()) << r.refused;
  ASSERT_EQ(r.levels.size(), 3u);
  EXPECT_EQ(r.user_level, 1);
  EXPECT_NEAR(r.levels[1].spacing_m, 2.5e-3, 1e-9);
  ASSERT_EQ(r.outputs.size(), 1u);
  const ConvergenceOutput& tip = r.outputs[0];
  ASSERT_EQ(tip.status, "extrapolated");
  const auto [reference, uncertainty] = cantilever_reference();
  const double truth = tip.values[1] / reference - 1.0;
  std::printf(
      "cantilever at 2.5 mm: estimated error %+.2f %%, bound %.2f %%; against CalculiX %+.2f %% (+-%.2f %%), "
      "observed order %.2f\n",
      100.0 * tip.user_error, 100.0 * tip.user_bound, 100.0 * truth, 100.0 * uncertainty / reference,
      tip.estimate.order);
  EXPECT_LE(std::abs(truth), tip.user_bound + uncertainty / reference);
  EXPECT_GT(tip.user_error * truth, 0.0);  // the same sign: the beam is soft at 2.5 mm
  EXPECT_TRUE(std::filesystem::exists(dir / "convergence.csv"));
  EXPECT_TRUE(std::filesystem::exists(dir / "convergence.json"));
}

// At the default ratio sqrt(2) the beam's cells across the section go 4, 3, 2: the deflection goes 1.007,
// 0.981, 1.064 of Timoshenko's, and the command says so instead of printing an error.
TEST(ConvergenceStudy, ASequenceThatGoesUpAndDownGivesNoNumber) {
  const auto dir = test::fresh_test_dir();
  const test::CliCapture c = test::run_cli_captured(
      {"-q", "converge", test::source_path("scenes/cantilever.json"), "--out", dir.string(), "--no-plot"});
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_TRUE(c.out_has("no estimate (oscillating)")) << c.out;
  EXPECT_TRUE(c.out_has("not in the asymptotic range")) << c.out;
  EXPECT_FALSE(c.out_has("estimated error")) << c.out;
}

// The catheter on a short piece of the vein at 0.6 mm: with a column of nodes under its tip and with the
// lattice turned half a column, the nearest node's offset from the tool's axis differs by far more than the
// tolerance, and the signature says which tool differs; the same lattice twice matches.
TEST(ConvergenceStudy, LatticesWhoseNodesFallDifferentlyUnderTheToolDiffer) {
  const std::vector<std::string> piece = {
      "geometry.node_spacing_m=0.6e-3", "geometry.centerline.length_m=6e-3",
      "obstacles.0.tip_m=[0, 1.5e-3, 3e-3]", "geometry.lattice_angle_deg=90"};
  const Scene under = load_scene(test::source_path("scenes/hand-dorsal-vein-catheter.json"), piece);
  std::vector<std::string> turned_sets = piece;
  turned_sets.back() = "geometry.lattice_angle_deg=102.857";  // 14 columns: half a column is 12.857 deg
  const Scene turned = load_scene(test::source_path("scenes/hand-dorsal-vein-catheter.json"), turned_sets);
  auto a = build_run(under), b = build_run(turned), c = build_run(under);
  const LatticeSignature sa = lattice_signature(*a), sb = lattice_signature(*b), sc = lattice_signature(*c);
  ASSERT_FALSE(sa.entries.empty());
  EXPECT_TRUE(sa.mismatch(sc).empty()) << sa.mismatch(sc);
  const std::string m = sb.mismatch(sa);
  EXPECT_NE(m.find("tool 'catheter'"), std::string::npos) << m;
  EXPECT_EQ(sa.wall_layers, 4);
}

// `check` on a vessel the accuracy table does not cover: two lines, the nearest case with its independent
// error, and the command that estimates this scene's own error (not a list of every case).
TEST(ConvergenceStudy, CheckNamesTheNearestCaseAndTheConvergeCommand) {
  const std::string scene = test::source_path("scenes/hand-dorsal-vein-catheter.json");
  const test::CliCapture c =
      test::run_cli_captured({"-q", "check", scene, "--set", "geometry.node_spacing_m=0.6e-3", "--set",
                              "geometry.outer_radius_m=2e-3"});
  ASSERT_EQ(c.code, 0) << c.err;
  EXPECT_TRUE(c.out_has("not covered")) << c.out;
  EXPECT_TRUE(c.out_has("the nearest is 'hand dorsal vein, 6 Fr catheter")) << c.out;
  EXPECT_TRUE(c.out_has("vascsim converge " + scene)) << c.out;
  EXPECT_FALSE(c.out_has("cases: ")) << c.out;  // the old list of every case
  std::size_t lines = 0;
  for (std::size_t at = c.out.find("  accuracy  "); at != std::string::npos;
       at = c.out.find("  accuracy  ", at + 1))
    ++lines;
  EXPECT_EQ(lines, 2u) << c.out;
}

}  // namespace
}  // namespace vascsim
