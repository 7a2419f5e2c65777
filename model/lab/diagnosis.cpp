#include "diagnosis.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <future>
#include <set>

#include "data_checks.hpp"
#include "eye_confounds.hpp"
#include "model_family.hpp"

namespace rig::model {
namespace {

// The bars below were calibrated on effect-free zoo draws of the tuning seeds 20000-20007
// (`bench-lab --clean-only --seed 20000 --draws 8 --verbose` prints the figures), never on
// the seeds the rates are reported on. Population channel: eye-to-eye variation of 9 runs
// lets an IOP term gain up to ~16 % by chance, so less is not an effect (a covariate
// has its own bar, below).
constexpr double kMinGainPct = 16.0;
constexpr double kMinRunsImproved = 0.6;
constexpr double kMaxDeltaBic = -10.0;
// Close to the floor: at most this share of the baseline's excess over the floor left...
constexpr double kCloseShare = 0.30;
// ... or the CV RMSE at most this multiple of the floor (below it, no structure worth naming
// stands out: the sim's frozen tearing fluctuation alone leaves ~1.1x on clean data).
constexpr double kWellAbove = 1.5;  // effect-free baselines reach 1.4x their floor
// The within-eye channel's bars (its floor is the measurement noise alone): effect-free
// draws leave 1.2-2.2x the noise within eyes (the simulator's tearing and eye forms no
// eye parameter captures), and a flexible candidate gains up to 30 % on it by chance.
constexpr double kMinOwnEyeGainPct = 40.0;
constexpr double kOwnEyeWellAbove = 2.5;
// The most a candidate's rank loses for the channel it makes worse [percentage points].
constexpr double kOtherChannelPenaltyPct = 10.0;

// A covariate candidate regresses the eyes' own variation on a number drawn with each eye: on
// 24 effect-free draws of 9 eyes (tuning seeds 20000-20023, 2026-11-28) covariates gained up
// to 27.6 % by chance (6 forms of up to 4 parameters, 3 keys), the other candidates up to
// 14.4 %; covariates of the zoo at 3x the floor or more gained 36-80 %. So a covariate needs
// this much at 9 runs; a regression's chance gain falls as 1/runs, and so does the bar, down
// to kMinGainPct (at 17 runs or more: an extrapolation, the zoo draws 9).
constexpr double kMinCovariateGainPct9 = 30.0;
constexpr double kCalibrationRuns = 9.0;

double min_population_gain_pct(const std::string& candidate, std::size_t runs) {
  if (candidate.rfind("covariate:", 0) != 0) return kMinGainPct;
  return std::max(kMinGainPct, kMinCovariateGainPct9 * kCalibrationRuns /
                                   static_cast<double>(std::max<std::size_t>(runs, 1)));
}

std::array<double, kPhaseCount> sse_by_phase(const CvResult& cv,
                                             const std::vector<const PreparedRun*>& runs) {
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
  return static_cast<int>(term->shared_params().size()) +
         term->linear_columns() * static_cast<int>(runs);
}

// One channel's significance test of a candidate against the baseline.
struct ChannelTest {
  double gain_pct = 0.0;
  double runs_improved = 0.0;
  double delta_bic = 0.0;
  double n_effective = 0.0;
  bool passed = false;
};

ChannelTest test_channel(const std::vector<double>& base_sse, const std::vector<double>& sse,
                         const std::vector<std::size_t>& n, const std::vector<double>& rho,
                         int parameters, double min_gain_pct) {
  ChannelTest t;
  std::size_t improved = 0;
  double sse_base = 0.0, sse_cand = 0.0;
  for (std::size_t r = 0; r < sse.size() && r < base_sse.size(); ++r) {
    if (sse[r] < 0.995 * base_sse[r]) ++improved;
    sse_base += base_sse[r];
    sse_cand += sse[r];
    t.n_effective += static_cast<double>(n[r]) * (1.0 - rho[r]) / (1.0 + rho[r]);
  }
  t.gain_pct = sse_base > 0.0 ? 100.0 * (1.0 - std::sqrt(sse_cand / sse_base)) : 0.0;
  t.runs_improved =
      sse.empty() ? 0.0 : static_cast<double>(improved) / static_cast<double>(sse.size());
  const double n_eff = std::max(t.n_effective, 2.0);
  t.delta_bic = n_eff * std::log(std::max(sse_cand, 1e-300) / std::max(sse_base, 1e-300)) +
                parameters * std::log(n_eff);
  t.passed = t.gain_pct >= min_gain_pct && t.runs_improved >= kMinRunsImproved &&
             t.delta_bic < kMaxDeltaBic;
  return t;
}

// Both channels: significant if either passes (the population one sees effects that scale
// whole runs, the within-eye one effects with a shape inside the run).
void score(CandidateResult& c, const CvResult& base, const CvResult& cv, int parameters,
           bool unseen_eyes_alone) {
  const ChannelTest population =
      test_channel(base.run_sse, cv.run_sse, cv.run_n, cv.run_rho, parameters,
                   min_population_gain_pct(c.effect, cv.run_sse.size()));
  ChannelTest own = test_channel(base.own_eye_run_sse, cv.own_eye_run_sse, cv.run_n,
                                 cv.own_eye_run_rho, parameters, kMinOwnEyeGainPct);
  // A term that only scales whole runs is judged on unseen eyes (EffectTerm): 340016, a
  // sigmoid of post_mortem_h, was named `covariate:blade_uses` on 87.7 % within eyes beside
  // post_mortem_h's 71.7 % on unseen eyes.
  if (unseen_eyes_alone) own.passed = false;
  c.cv_rmse_N = cv.rmse_N;
  c.gain_pct = population.gain_pct;
  c.runs_improved = population.runs_improved;
  c.own_eye_cv_rmse_N = cv.own_eye_rmse_N;
  c.own_eye_gain_pct = own.gain_pct;
  c.own_eye_runs_improved = own.runs_improved;
  const ChannelTest& shown =
      own.passed && (!population.passed || own.gain_pct > population.gain_pct) ? own : population;
  c.delta_bic = shown.delta_bic;
  c.n_effective = shown.n_effective;
  c.significant = population.passed || own.passed;
  c.channel = population.passed && own.passed ? "both"
              : population.passed             ? "population"
              : own.passed                    ? "own eye"
                                              : "";
  // Ties between candidates are broken against one that makes the other channel worse (at
  // most kOtherChannelPenaltyPct): a term that fits shapes within eyes while it predicts
  // unseen eyes worse is less likely the cause than one that does both (draw 70046).
  const ChannelTest& other = &shown == &own ? population : own;
  c.rank_gain_pct = shown.gain_pct + std::clamp(other.gain_pct, -kOtherChannelPenaltyPct, 0.0);
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

Evaluated evaluate(const std::string& name, const ForceModel& model,
                   const EffectCatalogue& catalogue, const DiagnoseOptions& o,
                   const std::vector<const PreparedRun*>& runs, const CvResult& base) {
  Evaluated out;
  CandidateResult& c = out.result;
  c.effect = name;
  const auto term = catalogue.make(name);  // in the form chosen on all runs
  if (!term->applicable(runs, c.not_applicable) || !sampling_allows(name, runs, c.not_applicable)) {
    c.applicable = false;
    return out;
  }
  std::vector<std::string> effects = o.with;
  effects.push_back(name);
  const ModelFamily family(model, catalogue, effects);
  const CvResult cv = family.cross_validate(runs);
  score(c, base, cv, parameter_count(name, catalogue, runs.size()),
        term->judged_on_unseen_eyes_alone());
  out.floor = floor_of(family, cv.full, runs);
  c.floor_N = out.floor.total_N;
  c.explained_pct =
      base.rmse_N > c.floor_N ? 100.0 * (base.rmse_N - cv.rmse_N) / (base.rmse_N - c.floor_N) : 0.0;
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
  std::snprintf(
      numbers, sizeof numbers,
      " [CV RMSE %.4f -> %.4f N (%+.1f %%), most in the %s phase, %.0f %% of runs better]",
      base.rmse_N, cv.rmse_N, -c.gain_pct, c.where.c_str(), 100.0 * c.runs_improved);
  c.evidence = family.evidence(name, cv.full, runs) + numbers;
  if (!family.identifiable(name, cv.full, runs, c.not_applicable))
    c.applicable = false;  // never a verdict nor a partial one
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
  if (!c.converged)
    d.warnings.push_back(what + " " + c.effect +
                         ": its fit did not converge; its figures are those where it stopped");
  if (!c.left_start)
    d.warnings.push_back(what + " " + c.effect + ": its parameters never left their start values");
}

// Close to the floor on a channel: at most kCloseShare of the baseline's excess left, or
// not well above the floor.
bool close_to(double base, double after, double floor, double well_above) {
  return after - floor <= kCloseShare * (base - floor) || after <= well_above * floor;
}

bool close_on_its_channel(const Diagnosis& d, const CandidateResult& c) {
  const bool population = close_to(d.baseline_cv_rmse_N, c.cv_rmse_N, c.floor_N, kWellAbove);
  const bool own = close_to(d.baseline_own_eye_cv_rmse_N, c.own_eye_cv_rmse_N,
                            d.floor.measurement_N, kOwnEyeWellAbove);
  if (c.channel == "population") return population;
  if (c.channel == "own eye") return own;
  return population || own;
}

void name_effect(Diagnosis& d, const std::vector<Evaluated>& evaluated, const CandidateResult& c) {
  d.verdict = c.effect;
  for (const Evaluated& e : evaluated) {
    if (e.result.effect == c.effect) d.floor = e.floor;  // the floor of the model to adopt
  }
  d.noise_floor_N = d.floor.total_N;
  warn_about_fit(d, "verdict", c);
  if (c.cv_rmse_N > kWellAbove * c.floor_N ||
      c.own_eye_cv_rmse_N > kOwnEyeWellAbove * d.floor.measurement_N) {
    char text[240];
    std::snprintf(text, sizeof text,
                  "with %s the CV error is still %.1fx its floor (%.1fx the measurement noise "
                  "within eyes): diagnose again --with %s for the next effect",
                  c.effect.c_str(), c.cv_rmse_N / c.floor_N,
                  c.own_eye_cv_rmse_N / d.floor.measurement_N, c.effect.c_str());
    d.warnings.push_back(text);
  }
}

// The baseline's errors and floor, as the floor warnings read them (eye_confounds.hpp).
FloorReading baseline_reading(const Diagnosis& d) {
  return {d.baseline_cv_rmse_N, d.baseline_own_eye_cv_rmse_N, d.noise_floor_N,
          d.floor.measurement_N, d.floor.eye_variation_N};
}

// none | EFFECT | unexplained, from the ranked candidates (see diagnosis.hpp).
void decide(Diagnosis& d, const std::vector<Evaluated>& evaluated,
            const ResidualStructure& baseline_structure, std::size_t eyes) {
  const CandidateResult* significant = nullptr;
  for (const CandidateResult& c : d.candidates) {
    if (c.applicable && c.significant) {
      significant = &c;
      break;
    }
  }
  if (significant != nullptr) {
    if (close_on_its_channel(d, *significant)) return name_effect(d, evaluated, *significant);
    d.verdict = "unexplained";
    d.partial_candidate = significant->effect;
    for (const Evaluated& e : evaluated) {
      if (e.result.effect == significant->effect) d.unexplained_where = e.remaining;
    }
    warn_about_fit(d, "partial candidate", *significant);
    return;
  }
  const bool near_floor = d.baseline_cv_rmse_N <= kWellAbove * d.noise_floor_N &&
                          d.baseline_own_eye_cv_rmse_N <= kOwnEyeWellAbove * d.floor.measurement_N;
  if (near_floor) return;  // "none": nothing stands above the floor
  d.verdict = "unexplained";
  d.unexplained_where = baseline_structure;
  if (auto w = uncertain_floor_warning(baseline_reading(d), eyes, kWellAbove, kOwnEyeWellAbove))
    d.warnings.push_back(std::move(*w));
  if (!d.candidates.empty() && d.candidates.front().applicable &&
      d.candidates.front().gain_pct > 0.0) {
    d.partial_candidate = d.candidates.front().effect;
  }
}

std::vector<Evaluated> evaluate_all(const std::vector<std::string>& names, const ForceModel& model,
                                    const EffectCatalogue& catalogue, const DiagnoseOptions& o,
                                    const std::vector<const PreparedRun*>& runs,
                                    const CvResult& base) {
  // Each worker takes the next candidate as soon as it is free: candidates differ in cost by
  // 10x, and waiting for them in order left a core idle for a third of a diagnosis.
  std::vector<Evaluated> out(names.size());
  std::atomic<std::size_t> next{0};
  auto work = [&] {
    try {
      for (std::size_t i = next++; i < names.size(); i = next++)
        out[i] = evaluate(names[i], model, catalogue, o, runs, base);
    } catch (...) {
      next = names.size();  // the others stop after their current candidate
      throw;
    }
  };
  std::vector<std::future<void>> workers;
  const std::size_t threads =
      std::min<std::size_t>(static_cast<std::size_t>(std::max(o.threads, 1)), names.size());
  for (std::size_t t = 0; t < threads; ++t) workers.push_back(std::async(std::launch::async, work));
  for (auto& w : workers) w.get();  // rethrows a candidate's exception, after every worker stopped
  return out;
}

}  // namespace

NoiseFloor floor_of(const ModelFamily& family, const FitResult& full,
                    const std::vector<const PreparedRun*>& runs) {
  NoiseFloor f;
  f.measurement_N = noise_floor(runs);
  f.eye_spread = full.eye_spread;
  const double eye_N2 = family.eye_variance_N2(full, runs);
  f.eye_variation_N = std::sqrt(eye_N2);
  f.total_N = std::sqrt(f.measurement_N * f.measurement_N + eye_N2);
  return f;
}

Diagnosis diagnose(const ForceModel& model, const std::vector<RunData>& data,
                   const DiagnoseOptions& o) {
  Diagnosis d;
  std::vector<PreparedRun> prepared;
  prepared.reserve(data.size());
  std::size_t samples = 0;
  for (const RunData& r : data) samples += r.size();
  const RowBudget budget = row_budget(data.size(), samples);
  for (const RunData& r : data) {
    prepared.push_back(prepare_run(r, budget.fit_rows_per_run));
    thin_analysed(prepared.back(), budget.scored_per_run);
  }
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
  d.baseline_own_eye_cv_rmse_N = base.own_eye_rmse_N;
  d.floor = floor_of(base_family, base.full, runs);
  d.noise_floor_N = d.floor.total_N;
  if (!base.full.converged)
    d.warnings.push_back(
        "the baseline fit did not converge; its figures are those where it stopped");
  for (std::string& w : eye_confound_warnings(runs, base.full.eyes, covariate_keys(catalogue)))
    d.warnings.push_back(std::move(w));
  if (auto w = inflated_floor_warning(baseline_reading(d))) d.warnings.push_back(std::move(*w));
  std::vector<std::string> names;
  const std::set<std::string> present(d.base_effects.begin(), d.base_effects.end());
  for (const std::string& name : catalogue.candidates()) {
    const bool wanted =
        o.only.empty() || std::find(o.only.begin(), o.only.end(), name) != o.only.end();
    if (present.count(name) == 0U && wanted) names.push_back(name);
  }
  const std::vector<Evaluated> evaluated = evaluate_all(names, model, catalogue, o, runs, base);
  for (const Evaluated& e : evaluated) d.candidates.push_back(e.result);
  std::stable_sort(d.candidates.begin(), d.candidates.end(),
                   [](const CandidateResult& a, const CandidateResult& b) {
                     if (a.applicable != b.applicable) return a.applicable;
                     if (a.significant != b.significant) return a.significant;
                     if (a.significant) return a.rank_gain_pct > b.rank_gain_pct;
                     return a.cv_rmse_N < b.cv_rmse_N;
                   });
  decide(d, evaluated,
         locate_excess(runs, base.residuals, d.noise_floor_N, covariate_keys(catalogue)),
         runs.size());
  return d;
}

}  // namespace rig::model
