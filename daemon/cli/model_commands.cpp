#include "model_commands.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <sstream>

#include "comparison.hpp"
#include "diagnosis.hpp"
#include "html_report.hpp"
#include "lab_json.hpp"
#include "model_fit.hpp"
#include "model_lint.hpp"
#include "run_loader.hpp"

namespace rig::cli {
namespace {

struct LabOptions {
  std::vector<std::string> paths;
  std::string model;
  std::string report;
  std::string save;
  std::vector<std::string> add;
  std::vector<std::string> with;
  std::vector<std::string> only;
  bool refit = false;
  bool per_run = false;
};

std::vector<std::string> split_commas(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::stringstream in(item);
    std::string part;
    while (std::getline(in, part, ',')) {
      if (!part.empty()) out.push_back(part);
    }
  }
  return out;
}

void metrics_table(const std::vector<model::SegmentMetrics>& list) {
  Rows rows;
  for (const auto& m : list) {
    rows.push_back({m.segment, std::to_string(m.n), fixed(m.sse_N2, 5), fixed(m.r2, 3), fixed(m.rmse_N, 4), fixed(m.max_abs_N, 4), fixed(m.max_at_x_mm, 2)});
  }
  print_table({"segment", "n", "SSE N^2", "R^2", "RMSE N", "max N", "at x mm"}, rows);
}

int lint(const CliContext& c, const std::string& file) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(file));
  const auto findings = model::lint_model(m);
  if (c.json()) {
    std::cout << model::lint_json(m, findings).dump(2) << "\n";
  } else {
    std::cout << m.path << " (" << m.name << ")\n";
    for (const auto& f : findings) std::cout << "  " << model::to_string(f.severity) << ": " << f.what << "\n";
  }
  bool error = false;
  for (const auto& f : findings) error = error || f.severity == model::LintFinding::Severity::kError;
  return error ? 1 : 0;
}

int compare(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(o.model));
  const auto runs = load_runs(o.paths, c.archive_path);
  const model::Comparison cmp = model::compare(m, runs, o.refit);
  if (!o.report.empty()) {
    std::ofstream(o.report) << model::render_report(cmp, runs, model::find_uplot(executable_dir()));
    std::cerr << "report written to " << o.report << "\n";
  }
  if (c.json()) {
    std::cout << model::to_json(cmp).dump(2) << "\n";
    return 0;
  }
  std::cout << "model " << cmp.model_name << " on " << cmp.runs.size() << " run(s): RMSE " << fixed(cmp.overall.rmse_N, 4)
            << " N (noise floor " << fixed(cmp.noise_floor_N, 4) << " N), largest error " << fixed(cmp.overall.max_abs_N, 4)
            << " N at x = " << fixed(cmp.overall.max_at_x_mm, 2) << " mm in " << cmp.overall.max_in_run << "\n\nby phase\n";
  metrics_table(cmp.by_phase);
  std::cout << "\nby depth band\n";
  metrics_table(cmp.by_depth);
  Rows rows;
  for (const auto& t : cmp.covariates) rows.push_back({t.key, fixed(t.correlation, 2), fixed(t.slope_N_per_unit, 5)});
  std::cout << "\nrun RMSE against covariates\n";
  print_table({"covariate", "correlation", "slope N/unit"}, rows);
  std::cout << "\nresidual spectrum peaks: time";
  for (const auto& p : cmp.time_spectrum) std::cout << "  " << fixed(p.frequency, 2) << " Hz (" << fixed(p.amplitude_N, 4) << " N)";
  std::cout << "\n                         displacement";
  for (const auto& p : cmp.displacement_spectrum) std::cout << "  " << fixed(1.0 / p.frequency, 3) << " mm (" << fixed(p.amplitude_N, 4) << " N)";
  std::cout << "\n";
  return 0;
}

int diagnose(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(o.model));
  const auto runs = load_runs(o.paths, c.archive_path);
  model::DiagnoseOptions options;
  options.with = split_commas(o.with);
  options.only = split_commas(o.only);
  const model::Diagnosis d = model::diagnose(m, runs, options);
  if (c.json()) {
    std::cout << model::to_json(d).dump(2) << "\n";
    return 0;
  }
  std::cout << "baseline (" << m.name;
  for (const auto& e : d.base_effects) std::cout << " + " << e;
  std::cout << "): CV RMSE " << fixed(d.baseline_cv_rmse_N, 4) << " N, noise floor " << fixed(d.noise_floor_N, 4)
            << " N (measurement " << fixed(d.floor.measurement_N, 4) << " N, eye variation " << fixed(d.floor.eye_variation_N, 4)
            << " N)\n\n";
  Rows rows;
  for (const auto& cand : d.candidates) {
    if (!cand.applicable) {
      rows.push_back({cand.effect, "-", "-", "n/a", cand.not_applicable});
      continue;
    }
    rows.push_back({cand.effect, fixed(cand.cv_rmse_N, 4), fixed(cand.gain_pct, 1), cand.significant ? "yes" : "no", cand.evidence});
  }
  print_table({"effect", "CV RMSE N", "gain %", "significant", "evidence"}, rows);
  std::cout << "\nverdict: " << d.verdict << "\n";
  if (d.verdict == "unexplained") {
    std::cout << "where: " << d.unexplained_where.summary() << "\n";
    if (!d.partial_candidate.empty()) std::cout << "best partial candidate: " << d.partial_candidate << "\n";
  }
  for (const auto& w : d.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

int fit(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(o.model));
  const auto runs = load_runs(o.paths, c.archive_path);
  const model::FitReport f = model::fit_model(m, runs, split_commas(o.add), o.per_run);
  if (!o.save.empty()) {
    f.fitted.save(o.save);
    std::cerr << "model saved to " << o.save << "\n";
  }
  if (c.json()) {
    std::cout << model::to_json(f).dump(2) << "\n";
    return 0;
  }
  std::cout << "effects:";
  for (const auto& e : f.effects) std::cout << " " << e;
  std::cout << "\nCV RMSE " << fixed(f.before_cv_rmse_N, 4) << " N -> " << fixed(f.after_cv_rmse_N, 4) << " N (noise floor "
            << fixed(f.noise_floor_N, 4) << " N, " << fixed(f.after_cv_rmse_N / std::max(f.noise_floor_N, 1e-12), 2) << "x)\n\n";
  Rows rows;
  for (std::size_t i = 0; i < f.after_by_phase.size(); ++i) {
    const auto& a = f.after_by_phase[i];
    double before = 0.0;
    for (const auto& b : f.before_by_phase) {
      if (b.segment == a.segment) before = b.rmse_N;
    }
    rows.push_back({a.segment, fixed(before, 4), fixed(a.rmse_N, 4), fixed(a.max_abs_N, 4), fixed(a.max_at_x_mm, 2)});
  }
  print_table({"phase", "RMSE before N", "RMSE after N", "max after N", "at x mm"}, rows);
  std::cout << "\nparameters\n";
  for (const auto& [group, params] : f.params) {
    std::cout << "  " << group << ":";
    for (const auto& [k, v] : params) std::cout << " " << k << "=" << v;
    std::cout << "\n";
  }
  for (const auto& r : f.per_run) std::cout << "  per run " << r.label << ": RMSE " << fixed(r.rmse_N, 4) << " N\n";
  return 0;
}

}  // namespace

void add_model_commands(CLI::App& app, CliContext& c, int& exit_code) {
  CLI::App* model = app.add_subcommand("model", "the model lab: lint, compare, diagnose, fit")->require_subcommand(1);
  auto lint_file = std::make_shared<std::string>();
  CLI::App* lint_cmd = model->add_subcommand("lint", "report defects of a model file (discontinuities, missing values)");
  lint_cmd->add_option("model", *lint_file, "model file (default: the interpreted paper model)");
  lint_cmd->callback([&c, &exit_code, lint_file] { exit_code = lint(c, *lint_file); });
  auto o = std::make_shared<LabOptions>();
  auto common = [&o](CLI::App* cmd) {
    cmd->add_option("paths", o->paths, "run-CSV files, folders of them, or archive run ids")->required();
    cmd->add_option("--model", o->model, "model file (default: paper-interpreted.toml)");
  };
  CLI::App* cmp = model->add_subcommand("compare", "model against measurements: by run, phase, depth, covariate; spectra");
  common(cmp);
  cmp->add_option("--report", o->report, "write a self-contained HTML report");
  cmp->add_flag("--refit", o->refit, "refit the model's parameters across the runs first");
  cmp->callback([&c, &exit_code, o] { exit_code = compare(c, *o); });
  CLI::App* diag = model->add_subcommand("diagnose", "which physical effect is the model missing?");
  common(diag);
  diag->add_option("--with", o->with, "effects already accepted (E1,E2): diagnose what remains");
  diag->add_option("--only", o->only, "consider only these candidates");
  diag->callback([&c, &exit_code, o] { exit_code = diagnose(c, *o); });
  CLI::App* fit_cmd = model->add_subcommand("fit", "refit with added effects; before/after error per phase");
  common(fit_cmd);
  fit_cmd->add_option("--add", o->add, "effects to add: E1[,E2]");
  fit_cmd->add_option("--save", o->save, "save the fitted model file (for the overlay and the haptics)");
  fit_cmd->add_flag("--per-run", o->per_run, "also fit Eq. 1 to each run alone");
  fit_cmd->callback([&c, &exit_code, o] { exit_code = fit(c, *o); });
}

}  // namespace rig::cli
