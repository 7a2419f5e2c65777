#pragma once
// The lab archive from the command line: `rig runs pg:...` lists the runs of every rig,
// `rig export pg:... run=UUID` writes them as run-CSV, `rig lab-archive push pg:...` ships
// this rig's archive by hand (what rigd's replicator does continuously), e.g. from a rig
// whose rigd is off or was never configured for the lab.
#include <CLI/CLI.hpp>
#include <nlohmann/json_fwd.hpp>

#include <memory>
#include <string>
#include <vector>

#include "cli_context.hpp"

namespace rig::cli {

struct LabListOptions {
  std::vector<std::string> source;  // pg:CONNINFO key=value ...
  bool given() const { return !source.empty(); }
};

// Adds the optional pg: source (and filter options) to `rig runs`.
std::shared_ptr<LabListOptions> add_lab_runs_options(CLI::App* runs);
int list_lab_runs(const CliContext& c, const LabListOptions& o);
// `rig export pg:... [filters] -o FILE_OR_DIR`: one run to a file, several into a folder.
int export_lab_runs(const std::vector<std::string>& source, const std::string& output);
// One line for `rig status`: connected or why not, and the backlog.
std::string describe_lab_archive_status(const nlohmann::json& lab);
void add_lab_archive_commands(CLI::App& app, CliContext& c, int& exit_code);

}  // namespace rig::cli
