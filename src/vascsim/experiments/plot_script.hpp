#pragma once
// Pictures of experiments are drawn by Python scripts (matplotlib, Debian's /usr/bin/python3) from the CSV
// the experiment wrote; the C++ code only runs them. A missing script or a failing plot is not an error of
// the experiment: the caller reports it as a warning and keeps the data.

#include <filesystem>
#include <string>
#include <vector>

namespace vascsim {

struct PlotOutcome {
  std::filesystem::path png;  ///< the picture, when the script succeeded
  std::string problem;        ///< why there is none (empty when drawn)
};

/// scripts/<name> of the bundled files (core/bundled_files.hpp: the source tree of a build tree,
/// share/vascsim of an installed vascsim).
std::filesystem::path bundled_script(const std::string& name);

/// Runs `python script args...` (each argument quoted for the shell, stdout discarded); `png` is the picture
/// the arguments ask for.
PlotOutcome run_plot_script(const std::filesystem::path& script, const std::vector<std::string>& args,
                            const std::filesystem::path& png, const std::string& python = "/usr/bin/python3");

}  // namespace vascsim
