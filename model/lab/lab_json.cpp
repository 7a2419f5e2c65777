#include "lab_json.hpp"

#include <nlohmann/json.hpp>

namespace rig::model {

nlohmann::json to_json(const SegmentMetrics& m) {
  return {{"segment", m.segment},         {"n", m.n},
          {"sse_N2", m.sse_N2},           {"r2", m.r2},
          {"rmse_N", m.rmse_N},           {"max_abs_N", m.max_abs_N},
          {"max_at_x_mm", m.max_at_x_mm}, {"max_at_t_s", m.max_at_t_s},
          {"max_in_run", m.max_in_run}};
}

namespace {

nlohmann::json to_json(const EyeSpread& s) {
  return {{"precut_scale", s.precut_scale}, {"cut_scale", s.cut_scale}, {"x_pi_mm", s.x_pi_mm}};
}

nlohmann::json metrics_list(const std::vector<SegmentMetrics>& list) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& m : list) out.push_back(to_json(m));
  return out;
}

}  // namespace

nlohmann::json to_json(const Diagnosis& d) {
  nlohmann::json candidates = nlohmann::json::array();
  for (const CandidateResult& c : d.candidates) {
    nlohmann::json j = {{"effect", c.effect}, {"applicable", c.applicable}};
    if (c.applicable) {
      j.update({{"cv_rmse_N", c.cv_rmse_N},
                {"gain_pct", c.gain_pct},
                {"own_eye_cv_rmse_N", c.own_eye_cv_rmse_N},
                {"own_eye_gain_pct", c.own_eye_gain_pct},
                {"channel", c.channel},
                {"significant", c.significant},
                {"evidence", c.evidence},
                {"runs_improved", c.runs_improved},
                {"delta_bic", c.delta_bic},
                {"n_effective", c.n_effective},
                {"where", c.where},
                {"floor_N", c.floor_N},
                {"explained_pct", c.explained_pct},
                {"converged", c.converged},
                {"left_start", c.left_start}});
    } else {
      j.update({{"significant", false}, {"evidence", "not applicable: " + c.not_applicable}});
    }
    candidates.push_back(std::move(j));
  }
  nlohmann::json where = nlohmann::json::array();
  for (const ExcessBin& b : d.unexplained_where.bins) {
    where.push_back({{"view", b.view},
                     {"bin", b.bin},
                     {"share", b.share},
                     {"mean_residual_N", b.mean_residual_N}});
  }
  nlohmann::json result = {
      {"baseline",
       {{"cv_rmse_N", d.baseline_cv_rmse_N},
        {"own_eye_cv_rmse_N", d.baseline_own_eye_cv_rmse_N},
        {"noise_floor_N", d.noise_floor_N},
        {"effects", d.base_effects}}},
      {"noise_floor",
       {{"total_N", d.floor.total_N},
        {"measurement_N", d.floor.measurement_N},
        {"eye_variation_N", d.floor.eye_variation_N},
        {"eye_spread", to_json(d.floor.eye_spread)},
        {"definition",
         "sqrt(measurement^2 + eye_variation^2): white noise of the force channel plus the RMS "
         "that eye-to-eye variation (tissue-force scale, puncture depth) adds to a prediction "
         "for an eye not yet seen"}}},
      {"candidates", candidates},
      {"verdict", d.verdict},
      {"warnings", d.warnings}};
  if (d.verdict == "unexplained") {
    result["partial_candidate"] = d.partial_candidate;
    result["unexplained_where"] = {
        {"bins", where},
        {"covariate", d.unexplained_where.covariate},
        {"covariate_correlation", d.unexplained_where.covariate_correlation},
        {"summary", d.unexplained_where.summary()}};
  }
  return result;
}

nlohmann::json to_json(const FitReport& f) {
  nlohmann::json per_run = nlohmann::json::array();
  for (const RunFit& r : f.per_run)
    per_run.push_back({{"run", r.label}, {"rmse_N", r.rmse_N}, {"params", r.params}});
  return {
      {"effects", f.effects},
      {"before",
       {{"cv_rmse_N", f.before_cv_rmse_N}, {"by_phase", metrics_list(f.before_by_phase)}}},
      {"after", {{"cv_rmse_N", f.after_cv_rmse_N}, {"by_phase", metrics_list(f.after_by_phase)}}},
      {"noise_floor_N", f.noise_floor_N},
      {"noise_floor",
       {{"measurement_N", f.measurement_noise_N},
        {"eye_variation_N", f.eye_variation_N},
        {"eye_spread", to_json(f.eye_spread)}}},
      {"params", f.params},
      {"per_run", per_run},
      {"warnings", f.warnings}};
}

nlohmann::json to_json(const Comparison& c) {
  nlohmann::json runs = nlohmann::json::array();
  for (const RunComparison& r : c.runs) {
    runs.push_back({{"run", r.label},
                    {"metrics", to_json(r.overall)},
                    {"x_pi_mm", r.segmentation.x_pi_mm},
                    {"x_c_mm", r.segmentation.x_c_mm},
                    {"x_pf_mm", r.segmentation.x_pf_mm},
                    {"punctured", r.segmentation.punctured},
                    {"notes", r.segmentation.notes}});
  }
  nlohmann::json covariates = nlohmann::json::array();
  for (const CovariateTrend& t : c.covariates) {
    covariates.push_back({{"key", t.key},
                          {"correlation", t.correlation},
                          {"slope_N_per_unit", t.slope_N_per_unit},
                          {"values", t.values},
                          {"run_rmse_N", t.run_rmse_N}});
  }
  auto peaks = [](const std::vector<SpectrumPeak>& list, const char* unit) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& p : list) out.push_back({{unit, p.frequency}, {"amplitude_N", p.amplitude_N}});
    return out;
  };
  return {{"model", c.model_name},
          {"overall", to_json(c.overall)},
          {"noise_floor_N", c.noise_floor_N},
          {"by_phase", metrics_list(c.by_phase)},
          {"by_depth", metrics_list(c.by_depth)},
          {"runs", runs},
          {"covariates", covariates},
          {"time_spectrum", peaks(c.time_spectrum, "frequency_Hz")},
          {"displacement_spectrum", peaks(c.displacement_spectrum, "cycles_per_mm")},
          {"warnings", c.warnings}};
}

nlohmann::json lint_json(const ForceModel& model, const std::vector<LintFinding>& findings) {
  nlohmann::json list = nlohmann::json::array();
  for (const LintFinding& f : findings) {
    nlohmann::json j = {{"severity", to_string(f.severity)}, {"what", f.what}};
    if (f.size_N != 0.0)
      j.update({{"x_mm", f.x_mm}, {"iop_mmHg", f.iop_mmHg}, {"jump_N", f.size_N}});
    if (f.lowest_N != 0.0)
      j.update({{"x_mm", f.x_mm}, {"iop_mmHg", f.iop_mmHg}, {"lowest_N", f.lowest_N}});
    list.push_back(std::move(j));
  }
  return {{"model", model.name}, {"file", model.path}, {"findings", list}};
}

}  // namespace rig::model
