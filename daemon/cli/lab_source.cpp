#include "lab_source.hpp"

#include <stdexcept>

namespace rig::cli {
namespace {

// Filters given as options; one command runs per `rig` process, so one set suffices.
lab_archive::LabRunFilter& option_filters() {
  static lab_archive::LabRunFilter filters;
  return filters;
}

bool is_filter(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) return false;
  for (std::size_t i = 0; i < eq; ++i) {
    const char c = arg[i];
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_' && c != '-') return false;
  }
  return true;
}

}  // namespace

bool is_lab_source(const std::string& arg) {
  return arg.rfind("pg:", 0) == 0;
}

LabSource parse_lab_source(const std::vector<std::string>& args, std::size_t& i) {
  LabSource source;
  source.conninfo = args.at(i).substr(3);
  source.filter = option_filters();
  while (i + 1 < args.size() && is_filter(args[i + 1])) source.filter.add(args[++i]);
  return source;
}

void add_lab_filter_options(CLI::App* command) {
  auto& f = option_filters();
  command->add_option("--rig", f.rig, "pg: sources: runs of this rig only");
  command->add_option("--eye-lot", f.eye_lot, "pg: sources: runs of this eye lot only");
  command->add_option("--since", f.since,
                      "pg: sources: runs created at or after this date (ISO 8601)");
}

std::vector<model::RunData> load_lab_runs(const LabSource& source) {
  lab_archive::LabRunReader reader(source.conninfo);
  std::vector<model::RunData> runs;
  for (const auto& row : reader.list_runs(source.filter)) {
    if (row.samples == 0) continue;  // armed and never cut, or not shipped yet
    runs.push_back(reader.load_run(row.uuid));
  }
  if (runs.empty())
    throw std::runtime_error("pg:" + std::string(source.conninfo.empty() ? "" : "...") +
                             ": no run with samples matches the filters");
  return runs;
}

}  // namespace rig::cli
