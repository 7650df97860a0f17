#pragma once
// `vascsim view`: registered with the CLI (app/cli.hpp CommandAdder) by apps/vascsim when the viewer is
// built.

#include <vector>

#include "vascsim/app/command.hpp"

namespace vascsim::viewer {

void add_view_command(CLI::App& app, CliContext& ctx, std::vector<Command>& commands);

}  // namespace vascsim::viewer
