// `vascsim view` in a build without the viewer (VASCSIM_BUILD_VIEWER=OFF): it accepts whatever follows and
// says in one line why there is no window (exit code 2). The real command is viewer/view_command.cpp.

#include "vascsim/app/command.hpp"
#include "vascsim/core/error.hpp"

namespace vascsim {

void add_view_stub_command(CLI::App& app, CliContext& /*ctx*/, std::vector<Command>& commands) {
  CLI::App* view = app.add_subcommand("view", "Interactive viewer (not in this build)");
  view->allow_extras();
  view->prefix_command();
  commands.push_back(
      {view, [] {
         throw InputError(
             "this vascsim was built without the viewer: configure with -DVASCSIM_BUILD_VIEWER=ON "
             "(the GL packages are in scripts/install-deps.sh)");
         return 2;
       }});
}

}  // namespace vascsim
