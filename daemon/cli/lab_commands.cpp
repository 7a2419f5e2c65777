#include "lab_commands.hpp"

#include <nlohmann/json.hpp>

#include <unistd.h>

#include <filesystem>
#include <iostream>

#include "lab_archive_settings.hpp"
#include "lab_run_reader.hpp"
#include "lab_schema.hpp"
#include "lab_source.hpp"
#include "run_csv.hpp"
#include "run_shipper.hpp"

namespace rig::cli {
namespace {

LabSource single_source(const std::vector<std::string>& args) {
  if (args.empty() || !is_lab_source(args[0]))
    throw std::runtime_error("expected a pg:CONNINFO source first");
  std::size_t i = 0;
  LabSource source = parse_lab_source(args, i);
  if (i + 1 != args.size())
    throw std::runtime_error(args[i + 1] + ": expected a filter key=value after the pg: source");
  return source;
}

std::string maybe(const std::optional<double>& value, int decimals) {
  return value ? fixed(*value, decimals) : "-";
}

struct PushOptions {
  std::vector<std::string> source;
  std::string rig_id;
  std::string password_file;
  std::string sslmode = "prefer";
  std::int64_t batch = 50000;
};

int push_archive(const CliContext& c, const PushOptions& o) {
  lab_archive::LabArchiveSettings settings;
  settings.conninfo = single_source(o.source).conninfo;
  settings.password_file = o.password_file;
  settings.sslmode = o.sslmode;
  settings.rig_id = o.rig_id.empty() ? lab_archive::default_rig_id() : o.rig_id;
  lab_archive::PgConnection db(lab_archive::connection_params(settings));
  lab_archive::create_or_migrate_lab_schema(db);
  lab_archive::RunShipper shipper(c.archive_path, settings.rig_id, "rig push");
  std::int64_t total = 0;
  while (const std::int64_t shipped = shipper.ship_pass(db, o.batch)) {
    total += shipped;
    if (!c.json() && isatty(STDERR_FILENO) == 1)
      std::cerr << "\r" << total << " samples shipped" << std::flush;
  }
  const lab_archive::Backlog left = shipper.backlog();
  if (c.json()) {
    std::cout << nlohmann::json{{"rig_id", settings.rig_id},
                                {"samples_shipped", total},
                                {"backlog_samples", left.samples},
                                {"backlog_runs", left.runs}}
                     .dump()
              << "\n";
  } else {
    if (isatty(STDERR_FILENO) == 1) std::cerr << "\r";
    std::cout << "rig " << settings.rig_id << ": " << total << " samples shipped, backlog "
              << left.runs << " runs, " << left.samples
              << " samples (runs still recording stay in the backlog)\n";
  }
  return 0;
}

}  // namespace

std::shared_ptr<LabListOptions> add_lab_runs_options(CLI::App* runs) {
  auto o = std::make_shared<LabListOptions>();
  runs->add_option("source", o->source,
                   "pg:CONNINFO [key=value...]: the lab archive instead of this rig's runs");
  add_lab_filter_options(runs);
  return o;
}

int list_lab_runs(const CliContext& c, const LabListOptions& o) {
  const LabSource source = single_source(o.source);
  lab_archive::LabRunReader reader(source.conninfo);
  const auto runs = reader.list_runs(source.filter);
  if (c.json()) {
    nlohmann::json list = nlohmann::json::array();
    for (const auto& r : runs) {
      list.push_back({{"run_uuid", r.uuid},
                      {"rig_id", r.rig_id},
                      {"run_id", r.local_run_id},
                      {"eye_id", r.eye_id},
                      {"eye_lot", r.eye_lot},
                      {"started_at", r.started_at},
                      {"outcome", r.outcome},
                      {"samples", r.samples}});
    }
    std::cout << nlohmann::json{{"runs", list}}.dump() << "\n";
    return 0;
  }
  Rows rows;
  for (const auto& r : runs) {
    rows.push_back({r.uuid, r.rig_id, std::to_string(r.local_run_id), r.eye_id,
                    r.eye_lot.empty() ? "-" : r.eye_lot, r.started_at, maybe(r.iop_mmHg, 1),
                    maybe(r.velocity_mm_s, 2), std::to_string(r.samples), r.outcome});
  }
  print_table({"run uuid", "rig", "run", "eye", "eye lot", "started (UTC)", "IOP mmHg", "v mm/s",
               "samples", "outcome"},
              rows);
  return 0;
}

int export_lab_runs(const std::vector<std::string>& args, const std::string& output) {
  const LabSource source = single_source(args);
  lab_archive::LabRunReader reader(source.conninfo);
  const auto runs = reader.list_runs(source.filter);
  if (runs.empty()) throw std::runtime_error("no run of the lab archive matches the filters");
  if (runs.size() == 1 && !std::filesystem::is_directory(output)) {
    const model::RunData run = reader.load_run(runs[0].uuid);
    if (output.empty() || output == "-") {
      model::write_run_csv(run, std::cout);
    } else {
      model::write_run_csv(run, output);
      std::cerr << "run " << runs[0].uuid << ": " << run.size() << " samples written to " << output
                << "\n";
    }
    return 0;
  }
  if (output.empty() || !std::filesystem::is_directory(output)) {
    throw std::runtime_error(std::to_string(runs.size()) +
                             " runs match: give -o an existing folder");
  }
  for (const auto& row : runs) {
    const std::string file = (std::filesystem::path(output) /
                              (row.rig_id + "-run" + std::to_string(row.local_run_id) + ".csv"))
                                 .string();
    model::write_run_csv(reader.load_run(row.uuid), file);
  }
  std::cerr << runs.size() << " runs written to " << output << "\n";
  return 0;
}

std::string describe_lab_archive_status(const nlohmann::json& lab) {
  std::string text = lab.value("connected", false) ? "connected" : "NOT CONNECTED";
  text += " as " + lab.value("rig_id", std::string("?")) + ", backlog " +
          std::to_string(lab.value("backlog_runs", 0)) + " runs / " +
          std::to_string(lab.value("backlog_samples", 0)) + " samples";
  if (!lab.value("backlog_known", false)) text += " (not yet compared with the server)";
  const std::string error = lab.value("last_error", std::string());
  if (!error.empty()) text += "; " + error;
  return text;
}

void add_lab_archive_commands(CLI::App& app, CliContext& c, int& exit_code) {
  CLI::App* lab =
      app.add_subcommand("lab-archive", "the lab archive on PostgreSQL (docs/lab-archive.md)")
          ->require_subcommand(1);
  auto o = std::make_shared<PushOptions>();
  CLI::App* push =
      lab->add_subcommand("push", "ship this rig's archive (--archive) to the lab archive now");
  push->add_option("source", o->source, "pg:CONNINFO")->required();
  push->add_option("--rig-id", o->rig_id, "this rig's name in the lab (default: host name)");
  push->add_option("--password-file", o->password_file, "file holding the password (mode 0600)");
  push->add_option("--sslmode", o->sslmode, "libpq sslmode")
      ->check(CLI::IsMember({"disable", "allow", "prefer", "require", "verify-ca", "verify-full"}));
  push->add_option("--batch", o->batch, "most samples per transaction")
      ->check(CLI::Range(1, 10000000));
  push->callback([&c, &exit_code, o] { exit_code = push_archive(c, *o); });
}

}  // namespace rig::cli
