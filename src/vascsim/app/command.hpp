#pragma once
// How the `vascsim` subcommands plug into run_cli (cli.cpp): each command file registers its subcommand(s)
// on the CLI11 app and hands back the action to run when the user chose it. The action reads the options the
// parse filled in, writes to the context's streams and returns the exit code; errors are exceptions that
// run_cli maps to exit codes (InputError 2, NumericalError 3, anything else 1).

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <ostream>
#include <vector>

namespace vascsim {

struct Scene;
struct NavigationResult;

/// Exit code of a run that finished but with steps (or lockstep frames) that did not converge: everything is
/// written, but those steps are not equilibria (docs/architecture.md, "Errors and exit codes").
constexpr int kExitUnconverged = 4;

// The largest thread count (-j, OMP_NUM_THREADS, bench --threads). Beyond the cores, threads only wait for
// one another (docs/performance.md, section 6), and 256 is as many as the largest common machines have
// hardware threads (a two-socket server of 2 x 64 cores with SMT); a fixed bound rather than a multiple of
// this machine's cores, so that a command line valid on one machine is valid on another. It also keeps an
// absurd count (1024, 100000) away from OpenMP, which ends the process when it cannot create a team's threads
// (cli.cpp).
constexpr int kMaxThreads = 256;

/// Draws a finished navigation into `out_dir` and names each file written on `out` (`vascsim navigate
/// --pictures`). It needs OpenGL, which only the viewer library links: builds with the viewer install it in
/// the CliContext (viewer/navigation_pictures.hpp).
using NavigationPictureWriter = void (*)(const Scene& scene, const NavigationResult& result,
                                         const std::filesystem::path& out_dir, std::ostream& out);

/// What every command shares: the output streams and the global options (-q, -v, -j).
struct CliContext {
  std::ostream& out;
  std::ostream& err;
  bool quiet = false;
  bool verbose = false;
  int threads = 0;                                        ///< -j; 0: OpenMP's default
  NavigationPictureWriter navigation_pictures = nullptr;  ///< null: a build without the viewer
  /// True when `err` is this process's terminal (a redrawn progress bar instead of lines).
  bool err_is_terminal() const;
};

/// A registered (sub)command: the CLI11 node and what to run when it was parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// One per command file.
void add_run_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
/// `check`: build a scene as `run` would, solve nothing, report size, cost, accuracy, regions, tools.
void add_check_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
/// `converge`: a scene's discretisation error from coarser (and one finer) spacings (converge_command.cpp).
void add_converge_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
void add_experiment_commands(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
/// `experiment timing` (timing_experiment.cpp), under the `experiment` node add_experiment_commands makes.
void add_timing_experiment(CLI::App& experiment, CliContext& ctx, std::vector<Command>& commands);
void add_validate_commands(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
void add_bench_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
void add_ahp_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
void add_soak_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
/// `navigate`: the scene's flexible instrument through the vessel's lumen (navigate_command.cpp).
void add_navigate_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);
/// `view` in a build without the viewer: one line saying so, exit code 2 (the viewer's own is viewer/).
void add_view_stub_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);

}  // namespace vascsim
