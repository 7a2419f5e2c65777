#include "model_fit.hpp"

#include "diagnosis.hpp"
#include "model_family.hpp"

namespace rig::model {
namespace {

std::vector<SegmentMetrics> by_phase(const CvResult& cv, const std::vector<const PreparedRun*>& runs) {
  std::vector<MetricsAccumulator> acc;
  for (int p = 0; p < kPhaseCount; ++p) acc.emplace_back(phase_name(static_cast<Phase>(p)));
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const PreparedRun& run = *runs[r];
    for (std::size_t k = 0; k < run.analysed.size(); ++k) {
      const std::size_t i = run.analysed[k];
      acc[static_cast<std::size_t>(run.seg.phase[i])].add(run.data->force_N[i], cv.residuals[r][k], run.data->x_mm[i], run.data->t_s[i], run.label());
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

}  // namespace

FitReport fit_model(const ForceModel& model, const std::vector<RunData>& data, const std::vector<std::string>& add, bool per_run) {
  FitReport report;
  std::vector<PreparedRun> prepared;
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
  const ModelFamily after_family(model, catalogue, add);
  const CvResult after = after_family.cross_validate(runs);
  report.effects = after_family.effect_names();
  report.before_cv_rmse_N = before.rmse_N;
  report.after_cv_rmse_N = after.rmse_N;
  const NoiseFloor floor = floor_of(after_family, after.full, runs);
  report.noise_floor_N = floor.total_N;
  report.measurement_noise_N = floor.measurement_N;
  report.eye_variation_N = floor.eye_variation_N;
  report.eye_spread = floor.eye_spread;
  if (!after.full.converged) report.warnings.push_back("the fit did not converge; its parameters are those where it stopped");
  report.before_by_phase = by_phase(before, runs);
  report.after_by_phase = by_phase(after, runs);
  report.params["baseline"] = baseline_params(after.full.params.base);
  report.fitted = model;
  report.fitted.params = after.full.params.base;
  report.fitted.effects = after_family.settings(after.full.params);
  for (const EffectSetting& e : report.fitted.effects) report.params[e.name] = e.params;
  if (!add.empty()) report.fitted.name = model.name + "+" + add.front() + (add.size() > 1 ? "+..." : "");
  if (per_run) {
    for (const PreparedRun* run : runs) {
      const FitResult fit = Fitter(after_family.predictor(), {run}).fit(after.full.params, 300);
      report.per_run.push_back({run->label(), fit.rmse_N, baseline_params(fit.params.base)});
    }
  }
  return report;
}

}  // namespace rig::model
