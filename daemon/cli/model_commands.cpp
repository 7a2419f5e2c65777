#include "model_commands.hpp"

#include <nlohmann/json.hpp>

#include <fstream>
#include <iostream>
#include <sstream>

#include "comparison.hpp"
#include "data_checks.hpp"
#include "diagnosis.hpp"
#include "explanation_json.hpp"
#include "html_report.hpp"
#include "lab_json.hpp"
#include "lab_source.hpp"
#include "model_fit.hpp"
#include "model_lint.hpp"
#include "report/lab_views.hpp"
#include "report/report_file.hpp"
#include "residual_explainer.hpp"
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
  std::vector<std::string> terms;  // term files: user terms offered as candidates
  std::string save_term;
  std::string term_name = "explained";
  int max_features = 4;
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
    rows.push_back({m.segment, std::to_string(m.n), fixed(m.sse_N2, 5), fixed(m.r2, 3),
                    fixed(m.rmse_N, 4), fixed(m.max_abs_N, 4), fixed(m.max_at_x_mm, 2)});
  }
  print_table({"segment", "n", "SSE N^2", "R^2", "RMSE N", "max N", "at x mm"}, rows);
}

// The model file, with the user terms of the --terms files offered as candidates.
model::ForceModel load_model(const LabOptions& o) {
  model::ForceModel m = model::ForceModel::load(default_model_file(o.model));
  for (const std::string& file : o.terms) {
    for (model::UserTerm& term : model::load_user_terms(file))
      m.candidate_terms.push_back(std::move(term));
  }
  return m;
}

// Renders the report completely before anything is written, then writes it atomically: an
// error (assets missing, unwritable folder) leaves no file, or the old one untouched.
void write_report(const std::string& path, const std::string& kind,
                  const std::vector<model::RunData>& runs, const model::LabViews& views,
                  const nlohmann::json& lab) {
  const model::ReportAssets assets = model::find_report_assets(executable_dir());
  model::ReportContent content{kind, &views.before, views.after ? &*views.after : nullptr, lab};
  model::write_file_atomically(path, model::render_report(runs, content, assets));
  std::cerr << "report written to " << path << "\n";
}

int lint(const CliContext& c, const std::string& file) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(file));
  const auto findings = model::lint_model(m);
  if (c.json()) {
    std::cout << model::lint_json(m, findings).dump(2) << "\n";
  } else {
    std::cout << m.path << " (" << m.name << ")\n";
    for (const auto& f : findings)
      std::cout << "  " << model::to_string(f.severity) << ": " << f.what << "\n";
  }
  bool error = false;
  for (const auto& f : findings)
    error = error || f.severity == model::LintFinding::Severity::kError;
  return error ? 1 : 0;
}

int compare(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = model::ForceModel::load(default_model_file(o.model));
  const auto runs = load_runs(o.paths, c.archive_path);
  model::LabViews views = model::compare_views(m, runs, o.refit);
  if (o.refit) {
    for (auto& w : model::base_misfit_warnings(m, views.before))
      views.before.warnings.push_back(std::move(w));
  }
  const model::Comparison& cmp = views.before;
  if (!o.report.empty()) write_report(o.report, "compare", runs, views, model::to_json(cmp));
  for (const auto& w : cmp.warnings) std::cerr << "warning: " << w << "\n";
  if (c.json()) {
    std::cout << model::to_json(cmp).dump(2) << "\n";
    return 0;
  }
  std::cout << "model " << cmp.model_name << " on " << cmp.runs.size() << " run(s): RMSE "
            << fixed(cmp.overall.rmse_N, 4) << " N (noise floor " << fixed(cmp.noise_floor_N, 4)
            << " N), largest error " << fixed(cmp.overall.max_abs_N, 4)
            << " N at x = " << fixed(cmp.overall.max_at_x_mm, 2) << " mm in "
            << cmp.overall.max_in_run << "\n\nby phase\n";
  metrics_table(cmp.by_phase);
  std::cout << "\nby depth band\n";
  metrics_table(cmp.by_depth);
  Rows rows;
  for (const auto& t : cmp.covariates)
    rows.push_back({t.key, fixed(t.correlation, 2), fixed(t.slope_N_per_unit, 5)});
  std::cout << "\nrun RMSE against covariates\n";
  print_table({"covariate", "correlation", "slope N/unit"}, rows);
  std::cout << "\nresidual spectrum peaks: time";
  for (const auto& p : cmp.time_spectrum)
    std::cout << "  " << fixed(p.frequency, 2) << " Hz (" << fixed(p.amplitude_N, 4) << " N)";
  std::cout << "\n                         displacement";
  for (const auto& p : cmp.displacement_spectrum)
    std::cout << "  " << fixed(1.0 / p.frequency, 3) << " mm (" << fixed(p.amplitude_N, 4) << " N)";
  std::cout << "\n";
  return 0;
}

int diagnose(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = load_model(o);
  const auto runs = load_runs(o.paths, c.archive_path);
  model::DiagnoseOptions options;
  options.with = split_commas(o.with);
  options.only = split_commas(o.only);
  model::require_fittable(m, "diagnose");
  model::Diagnosis d = model::diagnose(m, runs, options);
  // The refitted baseline: what the report plots, and whether Eq. 1 describes these data.
  const model::LabViews views = model::diagnose_views(m, runs);
  for (auto& w : model::base_misfit_warnings(m, views.before)) d.warnings.push_back(std::move(w));
  if (!o.report.empty()) write_report(o.report, "diagnose", runs, views, model::to_json(d));
  if (c.json()) {
    std::cout << model::to_json(d).dump(2) << "\n";
    return 0;
  }
  std::cout << "baseline (" << m.name;
  for (const auto& e : d.base_effects) std::cout << " + " << e;
  std::cout << "): CV RMSE " << fixed(d.baseline_cv_rmse_N, 4) << " N, noise floor "
            << fixed(d.noise_floor_N, 4) << " N (measurement " << fixed(d.floor.measurement_N, 4)
            << " N, eye variation " << fixed(d.floor.eye_variation_N, 4) << " N)\n\n";
  Rows rows;
  for (const auto& cand : d.candidates) {
    if (!cand.applicable) {
      rows.push_back({cand.effect, "-", "-", "n/a", cand.not_applicable});
      continue;
    }
    rows.push_back({cand.effect, fixed(cand.cv_rmse_N, 4), fixed(cand.gain_pct, 1),
                    cand.significant ? "yes" : "no", cand.evidence});
  }
  print_table({"effect", "CV RMSE N", "gain %", "significant", "evidence"}, rows);
  std::cout << "\nverdict: " << d.verdict << "\n";
  if (d.verdict == "unexplained") {
    std::cout << "where: " << d.unexplained_where.summary() << "\n";
    if (!d.partial_candidate.empty()) {
      // Two effects at once leave each one's error above the floor: the next step is the same.
      std::cout << "best partial candidate: " << d.partial_candidate
                << " (with a second effect present, diagnose again --with " << d.partial_candidate
                << ")\n";
    }
  }
  for (const auto& w : d.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

int fit(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = load_model(o);
  const auto runs = load_runs(o.paths, c.archive_path);
  model::require_fittable(m, "fit");
  model::FitReport f = model::fit_model(m, runs, split_commas(o.add), o.per_run);
  const model::LabViews views = model::fit_views(m, f.fitted, runs);
  for (auto& w : model::base_misfit_warnings(m, views.before)) f.warnings.push_back(std::move(w));
  if (!o.report.empty()) write_report(o.report, "fit", runs, views, model::to_json(f));
  for (const auto& w : f.warnings) std::cerr << "warning: " << w << "\n";
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
  std::cout << "\nCV RMSE " << fixed(f.before_cv_rmse_N, 4) << " N -> "
            << fixed(f.after_cv_rmse_N, 4) << " N (noise floor " << fixed(f.noise_floor_N, 4)
            << " N, " << fixed(f.after_cv_rmse_N / std::max(f.noise_floor_N, 1e-12), 2) << "x)\n\n";
  Rows rows;
  for (std::size_t i = 0; i < f.after_by_phase.size(); ++i) {
    const auto& a = f.after_by_phase[i];
    double before = 0.0;
    for (const auto& b : f.before_by_phase) {
      if (b.segment == a.segment) before = b.rmse_N;
    }
    rows.push_back({a.segment, fixed(before, 4), fixed(a.rmse_N, 4), fixed(a.max_abs_N, 4),
                    fixed(a.max_at_x_mm, 2)});
  }
  print_table({"phase", "RMSE before N", "RMSE after N", "max after N", "at x mm"}, rows);
  std::cout << "\nparameters\n";
  for (const auto& [group, params] : f.params) {
    std::cout << "  " << group << ":";
    for (const auto& [k, v] : params) std::cout << " " << k << "=" << v;
    std::cout << "\n";
  }
  for (const auto& r : f.per_run)
    std::cout << "  per run " << r.label << ": RMSE " << fixed(r.rmse_N, 4) << " N\n";
  for (const auto& w : f.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

void print_explanation(const std::string& model_name, const model::explainer::Explanation& e) {
  std::cout << "baseline (" << model_name;
  for (const auto& effect : e.base_effects) std::cout << " + " << effect;
  std::cout << "): CV RMSE " << fixed(e.baseline_cv_rmse_N, 4) << " N, noise floor "
            << fixed(e.noise_floor_N, 4) << " N\n"
            << e.library_size << " candidate features; held-out RMSE along the path:";
  for (const auto& [size, rmse] : e.path)
    std::cout << "  " << size << ": " << fixed(rmse, 4) << " N";
  std::cout << "\n\n";
  if (!e.features.empty()) {
    Rows rows;
    for (const auto& f : e.features)
      rows.push_back(
          {f.parameter, f.expression, f.gate, fixed(f.coefficient, 6), fixed(f.contribution_N, 4)});
    print_table({"param", "feature", "phase", "coefficient", "RMS N"}, rows);
    std::cout << "\nterm user:" << e.term.name << " = " << e.term.expression << "  (phase "
              << e.term.phase << ")\n";
    std::cout << "predicted CV RMSE " << fixed(e.predicted_cv_rmse_N, 4) << " N ("
              << fixed(e.predicted_gain_pct, 1) << " % lower, " << fixed(100.0 * e.runs_improved, 0)
              << " % of runs better)\n";
  }
  if (e.validated) {
    std::cout << "fitted: CV RMSE " << fixed(e.after_cv_rmse_N, 4) << " N ("
              << fixed(e.after_gain_pct, 1) << " % lower, "
              << fixed(e.after_cv_rmse_N / std::max(e.noise_floor_N, 1e-12), 2)
              << "x the noise floor);";
    for (const auto& [k, v] : e.fitted.params) std::cout << " " << k << "=" << v;
    std::cout << "\n";
  }
  std::cout << "\n" << (e.proposed ? "proposed: " : "nothing proposed: ") << e.summary << "\n";
}

int explain(const CliContext& c, const LabOptions& o) {
  const model::ForceModel m = load_model(o);
  const auto runs = load_runs(o.paths, c.archive_path);
  model::explainer::ExplainOptions options;
  options.with = split_commas(o.with);
  options.term_name = o.term_name;
  options.max_features = o.max_features;
  const model::explainer::Explanation e = model::explainer::explain(m, runs, options);
  if (c.json()) {
    std::cout << model::explainer::to_json(e).dump(2) << "\n";
  } else {
    print_explanation(m.name, e);
  }
  if (!o.save_term.empty()) {
    if (e.proposed) {
      model::save_user_terms(o.save_term, {e.validated ? e.fitted : e.term});
      std::cerr << "term saved to " << o.save_term
                << ": add it with  rig model fit PATH... --terms " << o.save_term
                << " --add user:" << e.term.name << "\n";
    } else {
      std::cerr << "nothing proposed: " << o.save_term << " not written\n";
    }
  }
  for (const auto& w : e.warnings) std::cerr << "warning: " << w << "\n";
  return 0;
}

}  // namespace

void add_model_commands(CLI::App& app, CliContext& c, int& exit_code) {
  CLI::App* model =
      app.add_subcommand("model", "the model lab: lint, compare, diagnose, fit, explain")
          ->require_subcommand(1);
  auto lint_file = std::make_shared<std::string>();
  CLI::App* lint_cmd = model->add_subcommand(
      "lint", "report defects of a model file (discontinuities, missing values)");
  lint_cmd->add_option("model", *lint_file, "model file (default: the interpreted paper model)");
  lint_cmd->callback([&c, &exit_code, lint_file] { exit_code = lint(c, *lint_file); });
  auto o = std::make_shared<LabOptions>();
  auto common = [&o](CLI::App* cmd) {
    cmd->add_option(
           "paths", o->paths,
           "run-CSV files, folders of them, archive run ids, or pg:CONNINFO [key=value...]")
        ->required();
    add_lab_filter_options(cmd);
    cmd->add_option("--model", o->model, "model file (default: paper-interpreted.toml)");
  };
  CLI::App* cmp = model->add_subcommand(
      "compare", "model against measurements: by run, phase, depth, covariate; spectra");
  common(cmp);
  cmp->add_option("--report", o->report, "write a self-contained HTML report");
  cmp->add_flag("--refit", o->refit, "refit the model's parameters across the runs first");
  cmp->callback([&c, &exit_code, o] { exit_code = compare(c, *o); });
  CLI::App* diag = model->add_subcommand("diagnose", "which physical effect is the model missing?");
  common(diag);
  diag->add_option("--with", o->with, "effects already accepted (E1,E2): diagnose what remains");
  diag->add_option("--only", o->only, "consider only these candidates");
  diag->add_option("--terms", o->terms, "term files: their user terms are candidates too");
  diag->add_option("--report", o->report,
                   "write a self-contained HTML report (residuals of the refitted baseline)");
  diag->callback([&c, &exit_code, o] { exit_code = diagnose(c, *o); });
  CLI::App* fit_cmd =
      model->add_subcommand("fit", "refit with added effects; before/after error per phase");
  common(fit_cmd);
  fit_cmd->add_option("--add", o->add, "effects to add: E1[,E2]");
  fit_cmd->add_option("--save", o->save,
                      "save the fitted model file (for the overlay and the haptics)");
  fit_cmd->add_flag("--per-run", o->per_run, "also fit Eq. 1 to each run alone");
  fit_cmd->add_option("--terms", o->terms, "term files whose user terms --add user:NAME may add");
  fit_cmd->add_option("--report", o->report,
                      "write a self-contained HTML report (before/after overlays)");
  fit_cmd->callback([&c, &exit_code, o] { exit_code = fit(c, *o); });
  CLI::App* explain_cmd = model->add_subcommand(
      "explain", "propose a closed-form user term for what the residuals still carry");
  common(explain_cmd);
  explain_cmd->add_option("--with", o->with,
                          "effects already accepted (E1,E2): explain what remains");
  explain_cmd->add_option("--terms", o->terms, "term files (their names are not reused)");
  explain_cmd->add_option("--save-term", o->save_term, "write the proposed term to a term file");
  explain_cmd->add_option("--name", o->term_name, "name of the proposed term (default: explained)");
  explain_cmd->add_option("--max-features", o->max_features, "most features in the term")
      ->check(CLI::Range(1, 12));
  explain_cmd->callback([&c, &exit_code, o] { exit_code = explain(c, *o); });
}

}  // namespace rig::cli
