#include "vascsim/app/cli.hpp"

#include <fmt/format.h>
#include <omp.h>
#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>
#include <unistd.h>
#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <latch>
#include <thread>
#include <vector>

#include "vascsim/app/command.hpp"
#include "vascsim/core/build_info.hpp"
#include "vascsim/core/error.hpp"
#include "vascsim/core/interrupt.hpp"
#include "vascsim/core/text.hpp"
#include "vascsim/core/thread_default.hpp"
#include "vascsim/experiments/machine_info.hpp"

namespace vascsim {

bool CliContext::err_is_terminal() const {
  return &err == &std::cerr && isatty(STDERR_FILENO);
}

namespace {

void setup_logging(std::ostream& err, bool quiet, bool verbose) {
  auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(err);
  auto logger = std::make_shared<spdlog::logger>("vascsim", sink);
  logger->set_pattern("[%l] %v");
  logger->set_level(quiet ? spdlog::level::warn : verbose ? spdlog::level::debug : spdlog::level::info);
  spdlog::set_default_logger(logger);
}

// Every command's and subcommand's options accept -q, -v and -j after the subcommand too.
void fall_through(CLI::App& app) {
  for (CLI::App* sub : app.get_subcommands({})) {
    sub->fallthrough();
    fall_through(*sub);
  }
}

// libgomp ends the process (exit code 1, "libgomp: Thread creation failed") when it cannot create a thread of
// a team, at the first parallel region. So the threads -j asks for are started here first, all alive at once
// as OpenMP's team would be, and ended again: a limit on processes (ulimit -u) or on the address space for
// their stacks (ulimit -v) is then one line and exit code 2, before any work.
void check_threads_can_start(int threads, const std::string& source) {
  std::latch release(1);
  std::vector<std::thread> started;
  std::string failure;
  try {
    started.reserve(static_cast<std::size_t>(threads - 1));
    while (static_cast<int>(started.size()) < threads - 1)
      started.emplace_back([&release] { release.wait(); });
  } catch (const std::exception& e) {
    failure = e.what();
  }
  release.count_down();
  for (std::thread& t : started) t.join();
  if (!failure.empty())
    throw InputError(
        fmt::format("{}: only {} threads could be started ({}): a limit on processes (ulimit -u) or "
                    "on memory (ulimit -v) allows fewer; choose fewer threads",
                    source, started.size() + 1, failure));
}

// -j, else OMP_NUM_THREADS (read by OpenMP itself), else the cores other work leaves idle
// (thread_default.hpp).
void apply_thread_count(int requested) {
  if (requested > 0) {
    if (requested > 1) check_threads_can_start(requested, fmt::format("-j {}", requested));
    omp_set_num_threads(requested);
    return;
  }
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    // OpenMP reads it itself (a list of counts per nesting level: the first one is ours).
    char* end = nullptr;
    const long first = std::strtol(env, &end, 10);
    if (end != env && first > kMaxThreads)
      throw InputError(fmt::format("OMP_NUM_THREADS={}: at most {} threads (or -j N)", env, kMaxThreads));
    if (end != env && first > 1)
      check_threads_can_start(static_cast<int>(first), fmt::format("OMP_NUM_THREADS={}", env));
    return;
  }
  const int cores = omp_get_num_procs();
  const double load = load_average_1min();
  const int others = other_runnable_processes();
  const int threads = default_thread_count(cores, load, others);
  omp_set_num_threads(threads);
  // Said with -v only: an error must stay one line, and the README states the rule.
  spdlog::debug(
      "{} OpenMP thread{} of {} cores: the load average is {:.2f} and {} other process{} running now "
      "(-j N or OMP_NUM_THREADS=N chooses)",
      threads, threads == 1 ? "" : "s", cores, load, others, others == 1 ? " is" : "es are");
}

// An empty value is never meaningful (`--out ''` is no folder, `--record ''` no file): every option that
// takes a value rejects it at parse time instead of falling back to a default silently.
void reject_empty_values(CLI::App& app) {
  const CLI::Validator non_empty([](std::string& value) { return value.empty() ? "an empty value" : ""; }, "",
                                 "non-empty");
  for (CLI::Option* option : app.get_options())
    if (option->get_expected_min() > 0) option->check(non_empty);
  for (CLI::App* sub : app.get_subcommands({})) reject_empty_values(*sub);
}

}  // namespace

int run_cli(const std::vector<std::string>& args, std::ostream& out, std::ostream& err,
            const std::vector<CommandAdder>& extra_commands) {
  CLI::App app{
      "vascsim: point-primitive vascular tissue simulation (Zhang et al. 2021, with the fixes of "
      "docs/model.md)"};
  app.require_subcommand(1);
  CliContext ctx{out, err};
  app.add_flag("-q,--quiet", ctx.quiet, "Only warnings and errors on stderr");
  app.add_flag("-v,--verbose", ctx.verbose, "Debug logging");
  app.add_option(
         "-j,--threads", ctx.threads,
         fmt::format("OpenMP threads, 1 to {} (default: OMP_NUM_THREADS if set, else the cores the load "
                     "average leaves idle, at least 1)",
                     kMaxThreads))
      ->check(CLI::Range(1, kMaxThreads));
  std::vector<Command> commands;
  add_run_command(app, ctx, commands);
  add_check_command(app, ctx, commands);
  add_converge_command(app, ctx, commands);
  add_validate_commands(app, ctx, commands);
  add_bench_command(app, ctx, commands);
  add_experiment_commands(app, ctx, commands);
  add_ahp_command(app, ctx, commands);
  add_soak_command(app, ctx, commands);
  add_navigate_command(app, ctx, commands);
  for (const CommandAdder add : extra_commands) add(app, ctx, commands);
  fall_through(app);
  reject_empty_values(app);
  // After fall_through: the stub keeps whatever follows it as its own extras.
  const bool viewer = std::any_of(commands.begin(), commands.end(),
                                  [](const Command& c) { return c.app->get_name() == "view"; });
  if (!viewer) add_view_stub_command(app, ctx, commands);
  app.set_version_flag(
      "--version",
      [viewer] {
        return format_build_info(build_info()) +
               "viewer: " + (viewer ? "on" : "off (built without VASCSIM_BUILD_VIEWER)");
      },
      "Print the version and the build configuration, then exit");

  std::vector<std::string> rev(args.rbegin(), args.rend());
  try {
    app.parse(rev);
  } catch (const CLI::CallForHelp&) {
    out << app.help();
    return 0;
  } catch (const CLI::CallForAllHelp&) {
    out << app.help("", CLI::AppFormatMode::All);
    return 0;
  } catch (const CLI::CallForVersion& e) {
    out << e.what() << "\n";
    return 0;
  } catch (const CLI::ParseError& e) {
    err << "vascsim: " << one_line(e.what()) << " (see vascsim --help)\n";
    return 2;
  }
  // The logger writes to `err`, which may not outlive this call: restore the previous one on return.
  struct RestoreLogger {
    std::shared_ptr<spdlog::logger> previous = spdlog::default_logger();
    ~RestoreLogger() { spdlog::set_default_logger(previous); }
  } restore_logger;
  setup_logging(err, ctx.quiet, ctx.verbose);
  const InterruptGuard interrupt_guard;
  try {
    apply_thread_count(ctx.threads);
    for (const Command& c : commands)
      if (c.app->parsed()) {
        const int code = c.run();
        if (!interrupt_requested()) return code;
        clear_interrupt();
        err << "vascsim: interrupted: stopped at a step boundary; the files written so far are complete\n";
        return kInterruptedExitCode;
      }
  } catch (const InputError& e) {
    err << "vascsim: error: " << one_line(e.what()) << "\n";
    return 2;
  } catch (const NumericalError& e) {
    err << "vascsim: numerical error: " << one_line(e.what()) << "\n";
    return 3;
  } catch (const std::exception& e) {
    err << "vascsim: internal error (please report): " << one_line(e.what()) << "\n";
    return 1;
  }
  return 0;
}

}  // namespace vascsim
