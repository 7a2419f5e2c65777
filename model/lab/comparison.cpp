#include "comparison.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>

#include "diagnosis.hpp"
#include "model_family.hpp"
#include "model_lint.hpp"
#include "residual_spectrum.hpp"

namespace rig::model {
namespace {

std::vector<std::string> numeric_keys(const std::vector<const PreparedRun*>& runs) {
  std::map<std::string, std::size_t> seen;
  for (const PreparedRun* r : runs) {
    for (const auto& [k, v] : r->data->meta) {
      if (r->data->number(k) && k != "run_id") ++seen[k];
    }
    for (const auto& c : r->data->channels) ++seen[c.name];
  }
  std::vector<std::string> out;
  for (const auto& [k, n] : seen) {
    if (n == runs.size()) out.push_back(k);
  }
  return out;
}

CovariateTrend trend(const std::string& key, const std::vector<const PreparedRun*>& runs,
                     const std::vector<RunComparison>& cmp) {
  CovariateTrend t;
  t.key = key;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    double sum = 0.0;
    for (const std::size_t i : runs[r]->analysed) sum += runs[r]->covariate(key, i).value_or(0.0);
    t.values.push_back(
        runs[r]->analysed.empty() ? 0.0 : sum / static_cast<double>(runs[r]->analysed.size()));
    t.run_rmse_N.push_back(cmp[r].overall.rmse_N);
  }
  const double n = static_cast<double>(t.values.size());
  double mx = 0, my = 0;
  for (std::size_t i = 0; i < t.values.size(); ++i)
    mx += t.values[i] / n, my += t.run_rmse_N[i] / n;
  double sxy = 0, sxx = 0, syy = 0;
  for (std::size_t i = 0; i < t.values.size(); ++i) {
    sxy += (t.values[i] - mx) * (t.run_rmse_N[i] - my);
    sxx += (t.values[i] - mx) * (t.values[i] - mx);
    syy += (t.run_rmse_N[i] - my) * (t.run_rmse_N[i] - my);
  }
  t.correlation = sxx > 0 && syy > 0 ? sxy / std::sqrt(sxx * syy) : 0.0;
  t.slope_N_per_unit = sxx > 0 ? sxy / sxx : 0.0;
  return t;
}

void add_spectra(const PreparedRun& run, const std::vector<double>& residual, Spectrum& in_time,
                 Spectrum& in_x) {
  std::vector<double> t, rt, x, rx;
  for (std::size_t k = 0; k < run.analysed.size(); ++k) {
    const std::size_t i = run.analysed[k];
    if (!t.empty() && run.data->t_s[i] <= t.back()) continue;  // duplicated times (digitised data)
    t.push_back(run.data->t_s[i]);
    rt.push_back(residual[k]);
    if (i <= run.seg.insertion_end && (x.empty() || run.data->x_mm[i] > x.back())) {
      x.push_back(run.data->x_mm[i]);
      rx.push_back(residual[k]);
    }
  }
  if (t.size() < 16) return;
  const double dt = (t.back() - t.front()) / static_cast<double>(t.size() - 1);
  in_time.add(t, rt, dt, 0.5 / dt);
  in_x.add(x, rx, 0.005, 20.0);  // 5 um steps, up to 20 cycles/mm
}

// The lab's family (Eq. 1 in our continuous reading plus the file's effects), optionally
// refitted across the runs first.
std::function<std::vector<double>(const PreparedRun&)> family_residuals(
    const ForceModel& model, const std::vector<const PreparedRun*>& runs, bool refit) {
  auto catalogue = std::make_shared<EffectCatalogue>(model, runs);
  auto family = std::make_shared<ModelFamily>(model, *catalogue, std::vector<std::string>{});
  ModelParams params = family->start(runs);
  if (refit) params = Fitter(family->predictor(), runs).fit(params, 400).params;
  return [catalogue, family, params](const PreparedRun& run) {
    return Fitter::residuals(family->predictor(), run, params, run.analysed);
  };
}

// Eq. 1 exactly as printed: evaluated as printed (never silently as our reading), with a
// warning that says so; it has no parameters the lab could refit.
std::function<std::vector<double>(const PreparedRun&)> printed_residuals(
    const ForceModel& model, bool refit, std::vector<std::string>& warnings) {
  if (refit) throw ModelFileError(printed_form_refusal(model, "refit"));
  if (!model.effects.empty() || !model.user_terms.empty()) {
    throw ModelFileError(model.path +
                         ": a printed-form model (form eq1-printed) cannot carry effects or terms: "
                         "the lab adds them to the continuous form only");
  }
  warnings.push_back(printed_form_warning(model));
  return [&model](const PreparedRun& run) {
    std::vector<double> out;
    out.reserve(run.analysed.size());
    for (const std::size_t i : run.analysed) {
      out.push_back(run.data->force_N[i] -
                    model.baseline(run.data->x_mm[i], run.front_mm[i], run.iop_mmHg));
    }
    return out;
  };
}

}  // namespace

namespace {

// The residual's spectra in time [Hz] and along x [1/mm], and their five largest peaks.
void finish_spectra(Spectrum& in_time, Spectrum& in_x, Comparison& out) {
  in_time.finish();
  in_x.finish();
  for (const auto& [f, a] : in_time.peaks(5, 0.5)) out.time_spectrum.push_back({f, a});
  for (const auto& [f, a] : in_x.peaks(5, 0.2)) out.displacement_spectrum.push_back({f, a});
  out.time_frequency_Hz = in_time.frequency;
  out.time_amplitude_N = in_time.amplitude;
  out.x_frequency_per_mm = in_x.frequency;
  out.x_amplitude_N = in_x.amplitude;
}

}  // namespace

Comparison compare(const ForceModel& model, const std::vector<RunData>& data, bool refit) {
  Comparison out;
  out.model_name = model.name;
  std::vector<PreparedRun> prepared;
  prepared.reserve(data.size());
  for (const RunData& r : data) prepared.push_back(prepare_run(r));
  std::vector<const PreparedRun*> runs;
  for (const PreparedRun& p : prepared) {
    runs.push_back(&p);
    out.warnings.insert(out.warnings.end(), p.warnings.begin(), p.warnings.end());
  }
  const std::function<std::vector<double>(const PreparedRun&)> residuals_of =
      model.form == ModelForm::kPrinted ? printed_residuals(model, refit, out.warnings)
                                        : family_residuals(model, runs, refit);
  std::vector<MetricsAccumulator> phases;
  phases.reserve(kPhaseCount);
  for (int p = 0; p < kPhaseCount; ++p) phases.emplace_back(phase_name(static_cast<Phase>(p)));
  std::vector<MetricsAccumulator> bands;
  MetricsAccumulator overall("all");
  Spectrum in_time, in_x;
  for (const PreparedRun* run : runs) {
    RunComparison rc;
    rc.label = run->label();
    rc.segmentation = run->seg;
    const std::vector<double> residual = residuals_of(*run);
    rc.prediction.assign(run->size(), 0.0);
    MetricsAccumulator mine(rc.label);
    for (std::size_t k = 0; k < run->analysed.size(); ++k) {
      const std::size_t i = run->analysed[k];
      const double y = run->data->force_N[i], x = run->data->x_mm[i], t = run->data->t_s[i];
      rc.prediction[i] = y - residual[k];
      phases[static_cast<std::size_t>(run->seg.phase[i])].add(y, residual[k], x, t, rc.label);
      mine.add(y, residual[k], x, t, rc.label);
      overall.add(y, residual[k], x, t, rc.label);
      if (i <= run->seg.insertion_end && x >= 0.0) {
        const auto band = static_cast<std::size_t>(x);
        while (bands.size() <= band)
          bands.emplace_back(std::to_string(bands.size()) + "-" + std::to_string(bands.size() + 1) +
                             " mm");
        bands[band].add(y, residual[k], x, t, rc.label);
      }
    }
    rc.overall = mine.finish();
    add_spectra(*run, residual, in_time, in_x);
    out.runs.push_back(std::move(rc));
  }
  for (const auto& p : phases) {
    if (p.finish().n > 0) out.by_phase.push_back(p.finish());
  }
  for (const auto& b : bands) out.by_depth.push_back(b.finish());
  out.overall = overall.finish();
  for (const auto& key : numeric_keys(runs)) out.covariates.push_back(trend(key, runs, out.runs));
  finish_spectra(in_time, in_x, out);
  out.noise_floor_N = noise_floor(runs);
  return out;
}

}  // namespace rig::model
