#include "diagnosis.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <future>
#include <set>

#include "data_checks.hpp"
#include "model_family.hpp"

namespace rig::model {
namespace {

constexpr double kMinGainPct = 5.0;  // below this, per-run structure the model must not chase (tearing) can pass
constexpr double kMinRunsImproved = 0.6;
constexpr double kMaxDeltaBic = -10.0;
// Close to the floor: at most this share of the baseline's excess over the floor left...
constexpr double kCloseShare = 0.30;
// ... or the CV RMSE at most this multiple of the floor (below it, no structure worth naming
// stands out: the sim's frozen tearing fluctuation alone leaves ~1.1x on clean data).
constexpr double kWellAbove = 1.3;

std::array<double, kPhaseCount> sse_by_phase(const CvResult& cv, const std::vector<const PreparedRun*>& runs) {
  std::array<double, kPhaseCount> sse{};
  for (std::size_t r = 0; r < runs.size(); ++r) {
    for (std::size_t k = 0; k < runs[r]->analysed.size(); ++k) {
      const double e = cv.residuals[r][k];
      sse[static_cast<std::size_t>(runs[r]->seg.phase[runs[r]->analysed[k]])] += e * e;
    }
  }
  return sse;
}

int parameter_count(const std::string& name, const EffectCatalogue& catalogue, std::size_t runs) {
  const auto term = catalogue.make(name);
  return static_cast<int>(term->shared_params().size()) + term->linear_columns() * static_cast<int>(runs);
}

void score(CandidateResult& c, const CvResult& base, const CvResult& cv, int parameters) {
  c.cv_rmse_N = cv.rmse_N;
  c.gain_pct = base.rmse_N > 0.0 ? 100.0 * (1.0 - cv.rmse_N / base.rmse_N) : 0.0;
  std::size_t improved = 0;
  double sse_base = 0.0, sse_cand = 0.0;
  for (std::size_t r = 0; r < cv.run_sse.size(); ++r) {
    if (cv.run_sse[r] < 0.995 * base.run_sse[r]) ++improved;
    sse_base += base.run_sse[r];
    sse_cand += cv.run_sse[r];
    const double rho = cv.run_rho[r];
    c.n_effective += static_cast<double>(cv.run_n[r]) * (1.0 - rho) / (1.0 + rho);
  }
  c.runs_improved = cv.run_sse.empty() ? 0.0 : static_cast<double>(improved) / static_cast<double>(cv.run_sse.size());
  const double n_eff = std::max(c.n_effective, 2.0);
  c.delta_bic = n_eff * std::log(std::max(sse_cand, 1e-300) / std::max(sse_base, 1e-300)) + parameters * std::log(n_eff);
  c.significant = c.gain_pct >= kMinGainPct && c.runs_improved >= kMinRunsImproved && c.delta_bic < kMaxDeltaBic;
}

std::vector<std::string> covariate_keys(const EffectCatalogue& catalogue) {
  std::vector<std::string> keys;
  for (const std::string& name : catalogue.candidates()) {
    if (name.rfind("covariate:", 0) == 0) keys.push_back(name.substr(10));
  }
  return keys;
}

// Whether the candidate's own parameters moved from where the fit started them.
bool term_left_start(const FitResult& fit) {
  if (fit.start_shared.empty() || fit.params.shared.empty()) return true;
  const auto& start = fit.start_shared.back();
  return start.empty() || start != fit.params.shared.back();
}

struct Evaluated {
  CandidateResult result;
  NoiseFloor floor;             // of baseline + this candidate
  ResidualStructure remaining;  // where its CV residuals still stand above its floor
};

Evaluated evaluate(const std::string& name, const ForceModel& model, const EffectCatalogue& catalogue,
                   const DiagnoseOptions& o, const std::vector<const PreparedRun*>& runs, const CvResult& base) {
  Evaluated out;
  CandidateResult& c = out.result;
  c.effect = name;
  if (!catalogue.make(name)->applicable(runs, c.not_applicable) || !sampling_allows(name, runs, c.not_applicable)) {
    c.applicable = false;
    return out;
  }
  std::vector<std::string> effects = o.with;
  effects.push_back(name);
  const ModelFamily family(model, catalogue, effects);
  const CvResult cv = family.cross_validate(runs);
  score(c, base, cv, parameter_count(name, catalogue, runs.size()));
  out.floor = floor_of(family, cv.full, runs);
  c.floor_N = out.floor.total_N;
  c.explained_pct = base.rmse_N > c.floor_N ? 100.0 * (base.rmse_N - cv.rmse_N) / (base.rmse_N - c.floor_N) : 0.0;
  c.converged = cv.full.converged;
  c.left_start = term_left_start(cv.full);
  out.remaining = locate_excess(runs, cv.residuals, c.floor_N, covariate_keys(catalogue));
  const auto before = sse_by_phase(base, runs);
  const auto after = sse_by_phase(cv, runs);
  std::size_t best = 0;
  for (std::size_t p = 1; p < before.size(); ++p) {
    if (before[p] - after[p] > before[best] - after[best]) best = p;
  }
  c.where = phase_name(static_cast<Phase>(best));
  char numbers[200];
  std::snprintf(numbers, sizeof numbers, " [CV RMSE %.4f -> %.4f N (%+.1f %%), most in the %s phase, %.0f %% of runs better]",
                base.rmse_N, cv.rmse_N, -c.gain_pct, c.where.c_str(), 100.0 * c.runs_improved);
  c.evidence = family.evidence(name, cv.full, runs) + numbers;
  return out;
}

}  // namespace

double noise_floor(const std::vector<const PreparedRun*>& runs) {
  double sum = 0.0;
  double n = 0.0;
  for (const PreparedRun* r : runs) {
    if (r->analysed.size() < 10) continue;
    const double s = noise_sigma(r->data->force_N, r->analysed.front(), r->analysed.back() + 1);
    sum += s * s * static_cast<double>(r->analysed.size());
    n += static_cast<double>(r->analysed.size());
  }
  return n > 0.0 ? std::sqrt(sum / n) : 0.0;
}

namespace {

void warn_about_fit(Diagnosis& d, const std::string& what, const CandidateResult& c) {
  if (!c.converged) d.warnings.push_back(what + " " + c.effect + ": its fit did not converge; its figures are those where it stopped");
  if (!c.left_start) d.warnings.push_back(what + " " + c.effect + ": its parameters never left their start values");
}

// none | EFFECT | unexplained, from the ranked candidates (see diagnosis.hpp).
void decide(Diagnosis& d, const std::vector<Evaluated>& evaluated, const ResidualStructure& baseline_structure) {
  const CandidateResult* significant = nullptr;
  for (const CandidateResult& c : d.candidates) {
    if (c.applicable && c.significant) {
      significant = &c;
      break;
    }
  }
  const double base = d.baseline_cv_rmse_N;
  if (significant != nullptr) {
    const double floor = significant->floor_N;
    const double after = significant->cv_rmse_N;
    const bool close = after - floor <= kCloseShare * (base - floor) || after <= kWellAbove * floor;
    if (close) {
      d.verdict = significant->effect;
      for (const Evaluated& e : evaluated) {
        if (e.result.effect == significant->effect) d.floor = e.floor;  // the floor of the model to adopt
      }
      d.noise_floor_N = d.floor.total_N;
      warn_about_fit(d, "verdict", *significant);
      if (after > kWellAbove * floor) {
        char text[200];
        std::snprintf(text, sizeof text, "with %s the CV error is still %.1fx its floor: diagnose again --with %s for the next effect",
                      significant->effect.c_str(), after / floor, significant->effect.c_str());
        d.warnings.push_back(text);
      }
      return;
    }
    d.verdict = "unexplained";
    d.partial_candidate = significant->effect;
    for (const Evaluated& e : evaluated) {
      if (e.result.effect == significant->effect) d.unexplained_where = e.remaining;
    }
    warn_about_fit(d, "partial candidate", *significant);
    return;
  }
  if (base <= kWellAbove * d.noise_floor_N) return;  // "none": nothing stands above the floor
  d.verdict = "unexplained";
  d.unexplained_where = baseline_structure;
  if (!d.candidates.empty() && d.candidates.front().applicable && d.candidates.front().gain_pct > 0.0) {
    d.partial_candidate = d.candidates.front().effect;
  }
}

std::vector<Evaluated> evaluate_all(const std::vector<std::string>& names, const ForceModel& model, const EffectCatalogue& catalogue,
                                    const DiagnoseOptions& o, const std::vector<const PreparedRun*>& runs, const CvResult& base) {
  std::vector<std::future<Evaluated>> pending;
  std::vector<Evaluated> out;
  std::size_t next = 0;
  auto launch = [&] {
    pending.push_back(std::async(std::launch::async, evaluate, names[next++], std::cref(model), std::cref(catalogue), std::cref(o),
                                 std::cref(runs), std::cref(base)));
  };
  for (int t = 0; t < std::max(o.threads, 1) && next < names.size(); ++t) launch();
  for (std::size_t i = 0; i < pending.size(); ++i) {
    out.push_back(pending[i].get());
    if (next < names.size()) launch();
  }
  return out;
}

}  // namespace

NoiseFloor floor_of(const ModelFamily& family, const FitResult& full, const std::vector<const PreparedRun*>& runs) {
  NoiseFloor f;
  f.measurement_N = noise_floor(runs);
  f.eye_spread = full.eye_spread;
  const double eye_N2 = family.eye_variance_N2(full, runs);
  f.eye_variation_N = std::sqrt(eye_N2);
  f.total_N = std::sqrt(f.measurement_N * f.measurement_N + eye_N2);
  return f;
}

Diagnosis diagnose(const ForceModel& model, const std::vector<RunData>& data, const DiagnoseOptions& o) {
  Diagnosis d;
  std::vector<PreparedRun> prepared;
  prepared.reserve(data.size());
  for (const RunData& r : data) prepared.push_back(prepare_run(r));
  add_run_order(prepared);
  std::vector<const PreparedRun*> runs;
  for (const PreparedRun& p : prepared) {
    runs.push_back(&p);
    d.warnings.insert(d.warnings.end(), p.warnings.begin(), p.warnings.end());
  }
  if (runs.empty()) throw std::invalid_argument("diagnose: no runs");
  append_sampling_warnings(runs, d.warnings);
  EffectCatalogue catalogue(model, runs);
  catalogue.set_baseline(o.with);  // forms are chosen over the baseline the user accepted (--with)
  const ModelFamily base_family(model, catalogue, o.with);
  d.base_effects = base_family.effect_names();
  const CvResult base = base_family.cross_validate(runs);
  d.baseline_cv_rmse_N = base.rmse_N;
  d.floor = floor_of(base_family, base.full, runs);
  d.noise_floor_N = d.floor.total_N;
  if (!base.full.converged) d.warnings.push_back("the baseline fit did not converge; its figures are those where it stopped");
  std::vector<std::string> names;
  const std::set<std::string> present(d.base_effects.begin(), d.base_effects.end());
  for (const std::string& name : catalogue.candidates()) {
    const bool wanted = o.only.empty() || std::find(o.only.begin(), o.only.end(), name) != o.only.end();
    if (present.count(name) == 0U && wanted) names.push_back(name);
  }
  const std::vector<Evaluated> evaluated = evaluate_all(names, model, catalogue, o, runs, base);
  for (const Evaluated& e : evaluated) d.candidates.push_back(e.result);
  std::stable_sort(d.candidates.begin(), d.candidates.end(), [](const CandidateResult& a, const CandidateResult& b) {
    if (a.applicable != b.applicable) return a.applicable;
    return a.cv_rmse_N < b.cv_rmse_N;
  });
  decide(d, evaluated, locate_excess(runs, base.residuals, d.noise_floor_N, covariate_keys(catalogue)));
  return d;
}

}  // namespace rig::model
