#pragma once
// rig haptic: play the model, a recorded run or the live rig on a (simulated) Phantom.
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_haptic_command(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
