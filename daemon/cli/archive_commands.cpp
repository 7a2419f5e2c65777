#include "archive_commands.hpp"

#include <nlohmann/json.hpp>

#include <iostream>

#include "archive.hpp"
#include "lab_commands.hpp"
#include "lab_source.hpp"
#include "run_csv.hpp"

namespace rig::cli {
namespace {

struct ExportOptions {
  std::vector<std::string> source;  // a run id, or pg:CONNINFO [key=value...]
  std::int64_t run_id = 0;
  bool csv = false;
  std::string output;
};

int export_run(const CliContext& c, const ExportOptions& o) {
  archive::Archive archive(c.archive_path, true);
  const model::RunData run = archive.load_run(o.run_id);
  if (o.output.empty() || o.output == "-") {
    model::write_run_csv(run, std::cout);
  } else {
    model::write_run_csv(run, o.output);
    std::cerr << "run " << o.run_id << ": " << run.size() << " samples written to " << o.output
              << "\n";
  }
  return 0;
}

int import_runs(const CliContext& c, const std::vector<std::string>& files) {
  archive::Archive archive(c.archive_path);
  // Not inside a running rigd's cut: rigd's recorder copies the log between runs, and the
  // last connection to close (this one, without rigd) copies it then.
  archive.defer_checkpoints();
  for (const std::string& source : archive.remove_abandoned_imports()) {
    std::cerr << "warning: removed a half-imported run of " << source
              << " (its rig import was stopped before the end); import the file again\n";
  }
  nlohmann::json imported = nlohmann::json::array();
  for (const auto& file : files) {
    const model::RunData run = model::read_run_csv(file);  // throws naming file and line
    for (const auto& warning : run.warnings) std::cerr << "warning: " << warning << "\n";
    const std::int64_t id = archive.import_run(run);
    imported.push_back({{"file", file}, {"run_id", id}, {"samples", run.size()}});
    if (!c.json())
      std::cout << file << ": imported as run " << id << " (" << run.size() << " samples)\n";
  }
  if (c.json()) std::cout << imported.dump() << "\n";
  return 0;
}

}  // namespace

void add_archive_commands(CLI::App& app, CliContext& c, int& exit_code) {
  auto e = std::make_shared<ExportOptions>();
  CLI::App* exp = app.add_subcommand("export", "write an archived run as run-CSV");
  exp->add_option(
         "run", e->source,
         "run id, or pg:CONNINFO [key=value...] (the lab archive; several runs: -o FOLDER)")
      ->required();
  exp->add_flag("--csv", e->csv, "run-CSV format (the only format)");
  exp->add_option("-o,--output", e->output, "file to write (default: standard output)");
  exp->callback([&c, &exit_code, e] {
    if (is_lab_source(e->source[0])) {
      exit_code = export_lab_runs(e->source, e->output);
      return;
    }
    if (e->source.size() != 1) throw CLI::ValidationError("run", "give one run id");
    if (!CLI::detail::lexical_cast(e->source[0], e->run_id))
      throw CLI::ValidationError("run", e->source[0] + ": not a run id");
    exit_code = export_run(c, *e);
  });
  add_lab_filter_options(exp);
  auto files = std::make_shared<std::vector<std::string>>();
  CLI::App* imp =
      app.add_subcommand("import", "read run-CSV files (ours or other DAQs') into the archive");
  imp->add_option("files", *files, "run-CSV files")->required()->check(CLI::ExistingFile);
  imp->callback([&c, &exit_code, files] { exit_code = import_runs(c, *files); });
}

}  // namespace rig::cli
