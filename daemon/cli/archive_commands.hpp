#pragma once
// `rig export RUN --csv` and `rig import FILE...`: the archive and run-CSV files. They open
// the archive directly (SQLite WAL allows it while rigd records), so data can be exported
// even when rigd is down.
#include <CLI/CLI.hpp>

#include "cli_context.hpp"

namespace rig::cli {

void add_archive_commands(CLI::App& app, CliContext& context, int& exit_code);

}  // namespace rig::cli
