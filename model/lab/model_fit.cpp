#include "model_fit.hpp"

#include <algorithm>
#include <stdexcept>

#include "diagnosis.hpp"
#include "model_family.hpp"

namespace rig::model {
namespace {

std::vector<SegmentMetrics> by_phase(const CvResult& cv,
                                     const std::vector<const PreparedRun*>& runs) {
  std::vector<MetricsAccumulator> acc;
  acc.reserve(kPhaseCount);
  for (int p = 0; p < kPhaseCount; ++p) acc.emplace_back(phase_name(static_cast<Phase>(p)));
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const PreparedRun& run = *runs[r];
    for (std::size_t k = 0; k < run.analysed.size(); ++k) {
      const std::size_t i = run.analysed[k];
      acc[static_cast<std::size_t>(run.seg.phase[i])].add(run.data->force_N[i], cv.residuals[r][k],
                                                          run.data->x_mm[i], run.data->t_s[i],
                                                          run.label());
    }
  }
  std::vector<SegmentMetrics> out;
  for (const auto& a : acc) {
    if (a.finish().n > 0) out.push_back(a.finish());
  }
  return out;
}

std::map<std::string, double> baseline_params(const ContinuousParams& p) {
  std::map<std::string, double> out;
  for (const BaselineParam& b : baseline_parameters()) out[b.name] = p.*(b.member);
  return out;
}

// The effects to add that are not in the model yet; the others are named in a warning.
std::vector<std::string> new_effects(const std::vector<std::string>& add,
                                     const std::vector<std::string>& present,
                                     std::vector<std::string>& warnings) {
  std::vector<std::string> out;
  for (const std::string& name : add) {
    const bool in_model = std::find(present.begin(), present.end(), name) != present.end();
    if (in_model || std::find(out.begin(), out.end(), name) != out.end()) {
      warnings.push_back(name + (in_model ? " is already in the model: not added again"
                                          : " was asked for twice: added once"));
      continue;
    }
    out.push_back(name);
  }
  return out;
}

// A user term must find every covariate it names in every run before it is fitted.
void check_user_terms(const ModelFamily& family, const EffectCatalogue& catalogue,
                      const std::vector<const PreparedRun*>& runs) {
  for (const std::string& name : family.effect_names()) {
    std::string why_not;
    if (name.rfind("user:", 0) == 0 && !catalogue.make(name)->applicable(runs, why_not))
      throw std::invalid_argument(name + ": " + why_not);
  }
}

}  // namespace

FitReport fit_model(const ForceModel& model, const std::vector<RunData>& data,
                    const std::vector<std::string>& add, bool per_run) {
  FitReport report;
  std::vector<PreparedRun> prepared;
  prepared.reserve(data.size());
  for (const RunData& r : data) prepared.push_back(prepare_run(r));
  add_run_order(prepared);
  std::vector<const PreparedRun*> runs;
  for (const PreparedRun& p : prepared) {
    runs.push_back(&p);
    report.warnings.insert(report.warnings.end(), p.warnings.begin(), p.warnings.end());
  }
  const EffectCatalogue catalogue(model, runs);
  const ModelFamily before_family(model, catalogue, {});
  const CvResult before = before_family.cross_validate(runs);
  const std::vector<std::string> added =
      new_effects(add, before_family.effect_names(), report.warnings);
  const ModelFamily after_family(model, catalogue, added);
  check_user_terms(after_family, catalogue, runs);
  const CvResult after = after_family.cross_validate(runs);
  report.effects = after_family.effect_names();
  report.before_cv_rmse_N = before.rmse_N;
  report.after_cv_rmse_N = after.rmse_N;
  const NoiseFloor floor = floor_of(after_family, after.full, runs);
  report.noise_floor_N = floor.total_N;
  report.measurement_noise_N = floor.measurement_N;
  report.eye_variation_N = floor.eye_variation_N;
  report.eye_spread = floor.eye_spread;
  if (!after.full.converged)
    report.warnings.push_back(
        "the fit did not converge; its parameters are those where it stopped");
  report.before_by_phase = by_phase(before, runs);
  report.after_by_phase = by_phase(after, runs);
  report.params["baseline"] = baseline_params(after.full.params.base);
  report.fitted = model;
  report.fitted.params = after.full.params.base;
  report.fitted.effects = after_family.settings(after.full.params);
  for (const EffectSetting& e : report.fitted.effects) report.params[e.name] = e.params;
  report.fitted.user_terms = after_family.user_terms(after.full.params);
  for (const UserTerm& u : report.fitted.user_terms) report.params["user:" + u.name] = u.params;
  std::erase_if(report.fitted.candidate_terms, [&](const UserTerm& c) {
    return std::any_of(report.fitted.user_terms.begin(), report.fitted.user_terms.end(),
                       [&](const UserTerm& u) { return u.name == c.name; });
  });
  if (!added.empty())
    report.fitted.name = model.name + "+" + added.front() + (added.size() > 1 ? "+..." : "");
  if (per_run) {
    for (const PreparedRun* run : runs) {
      const FitResult fit = Fitter(after_family.predictor(), {run}).fit(after.full.params, 300);
      report.per_run.push_back({run->label(), fit.rmse_N, baseline_params(fit.params.base)});
    }
  }
  return report;
}

}  // namespace rig::model
