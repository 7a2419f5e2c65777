#pragma once
// `rig sim generate`: runs of the simulated rig (through the real control loop on a
// virtual clock) written as run-CSV files, with hidden effects - data for the model lab.
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_sim_commands(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
