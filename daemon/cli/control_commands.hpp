#pragma once
// `rig status|home|tare|start|stop|estop|reset|run|runs`: run control through rigd's API.
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_control_commands(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
