#pragma once
// `pg:` sources on the command line: the lab archive on PostgreSQL instead of this rig's
// SQLite file. "pg:CONNINFO" (a libpq connection string or postgresql:// URI; "pg:" alone
// uses libpq's PG* environment variables) followed by filters key=value (rig=, eye_lot=,
// since=, run=, any metadata key), plus the --rig, --eye-lot and --since options.
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "lab_run_reader.hpp"
#include "run_data.hpp"

namespace rig::cli {

struct LabSource {
  std::string conninfo;
  lab_archive::LabRunFilter filter;
};

bool is_lab_source(const std::string& arg);
// Reads args[i] ("pg:...") and the key=value filters after it; leaves i on the last one used.
LabSource parse_lab_source(const std::vector<std::string>& args, std::size_t& i);
// --rig, --eye-lot, --since on a command: they apply to every pg: source of that command.
void add_lab_filter_options(CLI::App* command);
// The runs the source selects, in creation order; throws if none match.
std::vector<model::RunData> load_lab_runs(const LabSource& source);

}  // namespace rig::cli
