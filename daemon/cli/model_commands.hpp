#pragma once
// `rig model lint|compare|diagnose|fit`: the model lab from the command line.
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_model_commands(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
