// The VTK series a run writes on request: read back with a minimal independent parser (not the
// writer's code) and checked against the simulation's own state.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "vascsim/run/runner.hpp"
#include "vascsim/scene/scene.hpp"

namespace {

using namespace vascsim;

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The whitespace-separated numbers of <DataArray ... Name="name" ...> ... </DataArray>.
std::vector<double> data_array(const std::string& xml, const std::string& name) {
  const auto open = xml.find("Name=\"" + name + "\"");
  if (open == std::string::npos) return {};
  const auto begin = xml.find('>', open) + 1;
  const auto end = xml.find("</DataArray>", begin);
  std::istringstream in(xml.substr(begin, end - begin));
  std::vector<double> v;
  for (double x; in >> x;) v.push_back(x);
  return v;
}

TEST(OutputVtk, SeriesHoldsEveryStepWithConsistentDisplacements) {
  nlohmann::json doc = {
      {"name", "vtk-check"},
      {"geometry",
       {{"type", "box"}, {"min_m", {0, 0, 0}}, {"max_m", {4e-3, 2e-3, 2e-3}}, {"node_spacing_m", 1e-3}}},
      {"regions",
       {{{"name", "left"}, {"select", {{"type", "box"}, {"max_m", {0, 1, 1}}}}, {"bc", {{"type", "fixed"}}}},
        {{"name", "right"},
         {"select", {{"type", "box"}, {"min_m", {4e-3, -1, -1}}}},
         {"bc", {{"type", "displacement"}, {"vector_m", {1e-4, 0, 0}}}}}}},
      {"quasi_static", {{"load_steps", 2}}},
      {"output", {{"vtk", true}}}};
  const auto dir = std::filesystem::path(testing::TempDir()) / "vascsim-vtk-check";
  std::filesystem::remove_all(dir);
  RunOptions opt;
  opt.out_dir = dir;
  const auto summary = run_scene(parse_scene(doc, "vtk-check"), opt);
  const int nodes = summary["nodes"];
  EXPECT_EQ(nodes, 5 * 3 * 3);

  const std::string pvd = slurp(dir / "vtk" / "nodes.pvd");
  std::vector<std::string> files;
  for (auto pos = pvd.find("file=\""); pos != std::string::npos; pos = pvd.find("file=\"", pos + 1)) {
    const auto start = pos + 6;
    files.push_back(pvd.substr(start, pvd.find('"', start) - start));
  }
  ASSERT_EQ(files.size(), 3u);  // rest state and two load steps

  const std::string last = slurp(dir / "vtk" / files.back());
  auto attribute = [&](const std::string& name) {
    const auto pos = last.find(name + "=\"") + name.size() + 2;
    return std::stoi(last.substr(pos, last.find('"', pos) - pos));
  };
  EXPECT_EQ(attribute("NumberOfPoints"), nodes);
  EXPECT_EQ(attribute("NumberOfCells"), 6 * 4 * 2 * 2);  // Kuhn tets of 4 x 2 x 2 cells
  const auto u = data_array(last, "displacement");
  const auto x = data_array(last, "Points");
  ASSERT_EQ(u.size(), 3u * nodes);
  ASSERT_EQ(x.size(), 3u * nodes);
  // Nodes on the driven face (x = 4 mm at rest, so 4.1 mm now) moved by exactly the prescribed 0.1 mm;
  // clamped ones did not move.
  int driven = 0, clamped = 0;
  for (int i = 0; i < nodes; ++i) {
    const double rest_x = x[3 * i] - u[3 * i];
    if (std::abs(rest_x - 4e-3) < 1e-9) {
      EXPECT_NEAR(u[3 * i], 1e-4, 1e-12);
      ++driven;
    }
    if (std::abs(rest_x) < 1e-9) {
      EXPECT_NEAR(u[3 * i], 0.0, 1e-15);
      ++clamped;
    }
  }
  EXPECT_EQ(driven, 9);
  EXPECT_EQ(clamped, 9);
}

}  // namespace
