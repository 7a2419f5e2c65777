#include "stress_relaxation.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

StressRelaxation::StressRelaxation(int form) : FamilyTerm(form_names(), form) {}

const std::vector<std::string>& StressRelaxation::form_names() {
  static const std::vector<std::string> kNames = {"stretched exponential", "one exponential",
                                                  "two-term Prony", "power law"};
  return kNames;
}

std::vector<ParamSpec> StressRelaxation::shared_params() const {
  std::vector<ParamSpec> out = decay_params();
  out.push_back({"reload", "mm", 0.2, 0.01, 3.0});
  return out;
}

int StressRelaxation::reload_index() const {
  switch (form_) {
    case kOneExponential:
      return 2;
    case kProny:
      return 4;
    case kPowerLaw:
      return 2;
    default:
      return 3;
  }
}

std::vector<ParamSpec> StressRelaxation::decay_params() const {
  switch (form_) {
    case kOneExponential:
      return {{"r", "1", 0.0, -1.0, 1.0}, {"tau", "s", 1.0, 0.02, 60.0}};
    case kProny:
      return {{"r1", "1", 0.0, -1.0, 1.0},
              {"tau1", "s", 0.3, 0.02, 60.0},
              {"r2", "1", 0.0, -1.0, 1.0},
              {"tau2", "s", 10.0, 0.02, 600.0}};
    case kPowerLaw:
      return {{"n", "1", 0.0, -1.0, 2.0}, {"t0", "s", 0.1, 0.002, 60.0}};
    default:
      return {
          {"r", "1", 0.0, -1.0, 1.0}, {"tau", "s", 1.0, 0.02, 60.0}, {"beta", "1", 1.0, 0.2, 1.5}};
  }
}

std::vector<std::vector<double>> StressRelaxation::starts() const {
  std::vector<std::vector<double>> out;
  const std::vector<double> taus = {0.1, 0.3, 1.0, 3.0, 10.0, 30.0};
  for (const double tau : taus) {
    for (const double r : {0.1, 0.3}) {
      if (form_ == kOneExponential) out.push_back({r, tau});
      if (form_ == kStretched) out.push_back({r, tau, 0.5}), out.push_back({r, tau, 1.0});
    }
  }
  if (form_ == kProny) {
    for (const double fast : {0.03, 0.1, 0.3, 1.0}) {
      for (const double slow : {1.0, 3.0, 10.0, 30.0}) {
        if (slow <= fast) continue;
        for (const auto& [r_fast, r_slow] :
             {std::pair{0.15, 0.1}, std::pair{0.05, 0.2}, std::pair{0.2, 0.2}})
          out.push_back({r_fast, fast, r_slow, slow});
      }
    }
  }
  if (form_ == kPowerLaw) {
    for (const double t0 : {0.01, 0.1, 1.0}) {
      for (const double n : {0.05, 0.2, 0.5}) out.push_back({n, t0});
    }
  }
  std::vector<std::vector<double>> with_reload;  // each with a short and a long reload [mm]
  for (const double reload : {0.1, 0.5}) {
    for (auto start : out) {
      start.push_back(reload);
      with_reload.push_back(std::move(start));
    }
  }
  return with_reload;
}

bool StressRelaxation::applicable(const std::vector<const PreparedRun*>& runs,
                                  std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    const auto& s = r->seg;
    if (s.hold_end > s.hold_begin &&
        r->data->t_s[s.hold_end - 1] - r->data->t_s[s.hold_begin] >= 0.5)
      return true;
  }
  why_not = "no run holds at depth for 0.5 s or more";
  return false;
}

double StressRelaxation::decayed(double t, const double* p) const {
  switch (form_) {
    case kOneExponential:
      return -p[0] * std::expm1(-t / p[1]);
    case kProny:
      return -p[0] * std::expm1(-t / p[1]) - p[2] * std::expm1(-t / p[3]);
    case kPowerLaw:
      return 1.0 - std::pow(1.0 + t / p[1], -p[0]);
    default:
      return -p[0] * std::expm1(-std::pow(t / p[1], p[2]));
  }
}

namespace {

bool any_stop_on_the_way_in(const std::vector<const PreparedRun*>& runs) {
  return std::any_of(runs.begin(), runs.end(), [](const PreparedRun* r) {
    return std::any_of(r->reload_mm.begin(), r->reload_mm.end(), [](double v) { return v >= 0.0; });
  });
}

// The measured force at the start of the run's hold: mean over its first 20 ms, at most 20
// samples, at least one [N].
double hold_start_force(const PreparedRun& run) {
  const auto& seg = run.seg;
  const auto& t = run.data->t_s;
  std::size_t end = std::min(seg.hold_end, seg.hold_begin + 1);
  while (end < seg.hold_end && end < seg.hold_begin + 20 && t[end] < t[seg.hold_begin] + 0.02)
    ++end;
  double sum = 0.0;
  for (std::size_t i = seg.hold_begin; i < end; ++i) sum += run.data->force_N[i];
  return end > seg.hold_begin ? sum / static_cast<double>(end - seg.hold_begin) : 0.0;
}

// The model predicts (almost) no force where the run holds: the hold lies outside what the
// model describes (e.g. 30 mm deep in liver for a cornea model).
bool model_silent_in_hold(const PreparedRun& run, double model_force_N) {
  const double measured = hold_start_force(run);
  return measured > 0.0 && std::abs(model_force_N) < 0.1 * measured;
}

}  // namespace

double StressRelaxation::add(const SampleView& s, const double* p, double force_N) const {
  if (s.hold_s <= 0.0) {
    // Moving on after a stop: the relaxed tissue ahead reloads over `reload` mm of advance
    // (linearly: the blade meets fresh tissue in proportion to its advance).
    const auto& reload = s.run->reload_mm;
    if (s.i >= reload.size() || reload[s.i] < 0.0) return 0.0;
    const double left = 1.0 - reload[s.i] / p[reload_index()];
    return left > 0.0 ? -decayed(s.run->stop_length_s[s.i], p) * left * force_N : 0.0;
  }
  // In the hold or a stop, and after the hold while the blade withdraws.
  if (s.phase == Phase::kHold && model_silent_in_hold(*s.run, force_N)) {
    // Relax from the force measured when the hold began, since the model has none there.
    const double start = hold_start_force(*s.run);
    model_silent_ = true;
    return start * (1.0 - decayed(s.hold_s, p)) - force_N;
  }
  return -decayed(s.hold_s, p) * force_N;
}

// `reload` acts only where the blade moves on after a stop on the way in (the needle data
// insert, hold once at depth and withdraw: nothing reloads).
std::string StressRelaxation::uninformed_because(std::size_t k, const EvidenceInput& in) const {
  if (static_cast<int>(k) != reload_index() || any_stop_on_the_way_in(in.runs)) return {};
  return "no run stops on the way in";
}

std::string StressRelaxation::evidence(const EvidenceInput& in) const {
  double longest = 0.0;  // the longest hold [s]
  for (const PreparedRun* r : in.runs) {
    const auto& s = r->seg;
    if (s.hold_end > s.hold_begin)
      longest = std::max(longest, r->data->t_s[s.hold_end - 1] - r->data->t_s[s.hold_begin]);
  }
  const double* p = in.shared;
  const double lost = 100.0 * decayed(longest, p);
  std::string text;
  switch (form_) {
    case kOneExponential:
      text = format("one-exponential relaxation, %.2f s: ", p[1]);
      break;
    case kProny: {
      const bool first_fast = p[1] <= p[3];
      text =
          format("two-term relaxation, %.2f s and %.2f s (%.0f %% and ", first_fast ? p[1] : p[3],
                 first_fast ? p[3] : p[1], 100.0 * (first_fast ? p[0] : p[2])) +
          format("%.0f %% of the force): ", 100.0 * (first_fast ? p[2] : p[0]));
      break;
    }
    case kPowerLaw:
      text = format("power-law relaxation (1 + t/%.3f s)^-%.2f: ", p[1], p[0]);
      break;
    default:
      text =
          format("stretched-exponential relaxation, %.2f s, stretch exponent %.2f: ", p[1], p[2]);
      break;
  }
  if (model_silent_)
    text +=
        "the model predicts no force in some holds, so they relax from the force measured when the "
        "hold began: ";
  text += format("during holds the force decays by %.0f %% within %.1f s", lost, longest);
  if (any_stop_on_the_way_in(in.runs))
    text += format("; after a stop on the way in the tissue reloads over %.2f mm of advance",
                   p[reload_index()]);
  const double slowest = form_ == kProny ? std::max(p[1], p[3]) : (form_ == kPowerLaw ? 0.0 : p[1]);
  if (longest > 0.0 && slowest > 3.0 * longest) {
    text += format(
        "; the time constant %.3g s is beyond 3x the longest hold: not resolved, read it as a "
        "slow, almost linear decline",
        slowest);
  }
  return text + honesty(in);
}

}  // namespace rig::model::effects
