#pragma once
// `rig demo`: starts rig-sim and rigd, homes, tares, cuts (IOP 15 mmHg, 2 mm/s, 14 mm),
// prints a summary with the model comparison, then serves the live overlay until Ctrl-C
// (or exits at once with --once).
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_demo_command(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
