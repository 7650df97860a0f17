#include "vascsim/experiments/plot_script.hpp"

#include <fmt/format.h>
#include <cstdlib>

#include "vascsim/core/bundled_files.hpp"

namespace vascsim {

namespace {

// Quotes a word for /bin/sh.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q.append("'\\''");
    else
      q.push_back(c);
  }
  q.push_back('\'');
  return q;
}

}  // namespace

std::filesystem::path bundled_script(const std::string& name) {
  return bundled_file("scripts/" + name);
}

PlotOutcome run_plot_script(const std::filesystem::path& script, const std::vector<std::string>& args,
                            const std::filesystem::path& png, const std::string& python) {
  PlotOutcome out;
  if (!std::filesystem::exists(script)) {
    out.problem = fmt::format("{} not found", script.string());
    return out;
  }
  std::string cmd = shell_quote(python);
  cmd.append(" ").append(shell_quote(script.string()));
  for (const auto& a : args) cmd.append(" ").append(shell_quote(a));
  const std::string quiet = fmt::format("{} > /dev/null", cmd);
  const int rc = std::system(quiet.c_str());
  if (rc == 0)
    out.png = png;
  else
    out.problem = fmt::format("the plot script failed (exit status {}): {}", rc, cmd);
  return out;
}

}  // namespace vascsim
