#pragma once
// Runs named on the command line: a run-CSV file, a folder of them, an archive run id, or a
// lab archive source (pg:CONNINFO [key=value...], lab_source.hpp).
#include <string>
#include <vector>

#include "run_data.hpp"

namespace rig::cli {

// Throws naming the path (or run id) that could not be read; prints warnings to stderr.
std::vector<model::RunData> load_runs(const std::vector<std::string>& paths,
                                      const std::string& archive_path);
// The model file to use: the given one, or paper-interpreted.toml where rigd installs it.
std::string default_model_file(const std::string& given);
std::string executable_dir();

}  // namespace rig::cli
