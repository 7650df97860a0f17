#pragma once
// The `vascsim` command line, callable in-process (tests) with its own output streams.
//   vascsim --version   (the version and the build configuration)
//   vascsim [-q|-v] [-j THREADS] run SCENE.json [--set key=value ...] [--out DIR] [--yes]   (global options
//   may also follow the subcommand)
//   vascsim [-q|-v] check SCENE.json [--set key=value ...] [--yes] [--json FILE]   (builds, does not solve)
//   vascsim [-q|-v] [-j THREADS] validate cantilever [--out DIR] [--sizes 2,3,4,6]
//   vascsim [-q|-v] bench [SCENE.json] [--model xpbd] [--nodes 1000,3000,10000,30000] [--threads 1,2]
//     [--steps 200] [--warmup 20] [--set key=value ...] [--out FILE.csv|FILE.json ...]
//   vascsim [-q|-v] navigate SCENE.json [--set key=value ...] [--out DIR] [--pictures]
//   vascsim view SCENE.json [--set key=value ...] [--screenshot FILE.png --frames N --size WxH]  (viewer
//   builds)
// Exit codes: 0 success, 1 internal error (a bug), 2 bad input (scene, key, value, file; a run too large to
// start without --yes), 3 numerical failure (ill-conditioned discretisation, unstable or non-finite
// solution), 4 a run that finished with unconverged steps (command.hpp kExitUnconverged).

#include <ostream>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace vascsim {

struct CliContext;
struct Command;

/// Registers a command that lives outside this library (command.hpp): the viewer's `view`, which needs
/// OpenGL, or a part of one (the viewer's pictures for `navigate --pictures`, set in the CliContext).
/// apps/vascsim passes them when built with VASCSIM_BUILD_VIEWER.
using CommandAdder = void (*)(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);

/// Runs one command line. Without an adder for `view`, `vascsim view` says in one line that this build has no
/// viewer and exits with 2.
int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
            const std::vector<CommandAdder>& extra_commands = {});

}  // namespace vascsim
