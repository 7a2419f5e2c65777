#include "phases.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace rig::model {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}

namespace {

// Force smoothed over a window in displacement (not in samples: sampling may be irregular).
std::vector<double> smooth_in_x(const RunData& run, std::size_t end, double half_width_mm) {
  std::vector<double> out(end, 0.0);
  std::size_t lo = 0, hi = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < end; ++i) {
    while (hi < end && run.x_mm[hi] <= run.x_mm[i] + half_width_mm) sum += run.force_N[hi++];
    while (lo < hi && run.x_mm[lo] < run.x_mm[i] - half_width_mm) sum -= run.force_N[lo++];
    out[i] = hi > lo ? sum / static_cast<double>(hi - lo) : run.force_N[i];
  }
  return out;
}

// Index of the deepest point: the end of the insertion (first maximum of a smoothed x).
std::size_t deepest_index(const RunData& run) {
  const auto it = std::max_element(run.x_mm.begin(), run.x_mm.end());
  return static_cast<std::size_t>(it - run.x_mm.begin());
}

// First sample of the stay at `held` [mm] that ends at `deepest`: walking back while the
// position is within the hold's own jitter of it (3 robust SDs of `window`, at least 5 um:
// a pot's noise; a blade still arriving at 0.5 mm/s covers 5 um in 10 ms).
std::size_t arrival_index(const RunData& run, std::size_t deepest, double held,
                          const std::vector<double>& window) {
  std::vector<double> deviation;
  deviation.reserve(window.size());
  for (const double x : window) deviation.push_back(std::abs(x - held));
  const double tolerance_mm = std::max(0.005, 3.0 * 1.4826 * median(deviation));
  std::size_t begin = deepest;
  while (begin > 0 && run.x_mm[begin - 1] >= held - tolerance_mm) --begin;
  return begin;
}

void find_hold(const RunData& run, Segmentation& s) {
  // A hold starts where the blade arrived at its deepest position and lasts until the blade
  // has clearly withdrawn (0.2 mm: far beyond servo settling and overshoot); a turnaround is
  // no hold (< 0.5 s).
  constexpr double kWithdrawn_mm = 0.2;
  std::size_t end = s.insertion_end;
  while (end < run.size() && run.x_mm[end] >= s.max_depth_mm - kWithdrawn_mm) ++end;
  // The retraction begins where the blade starts to leave the held position (the median of
  // that window: the carriage settles back from its overshoot), not where it has left.
  std::vector<double> window(run.x_mm.begin() + static_cast<std::ptrdiff_t>(s.insertion_end),
                             run.x_mm.begin() + static_cast<std::ptrdiff_t>(end));
  const double held = median(window);
  std::size_t leave = end;
  while (leave > s.insertion_end + 1 && run.x_mm[leave - 1] < held - 0.02) --leave;
  // The hold begins where the blade arrived at the held position, not at the deepest sample:
  // a position's jitter in the hold (a digitized curve's 0.04 mm) can put that seconds late
  // (the needle data: 1.2 s into the hold, and the relaxation's fast part went unseen).
  const std::size_t arrived = arrival_index(run, s.insertion_end, held, window);
  if (run.t_s[leave - 1] - run.t_s[arrived] >= 0.5) {
    s.insertion_end = s.hold_begin = arrived;  // the insertion ends where the hold begins
    s.hold_end = leave;
  } else {
    s.hold_begin = s.hold_end =
        s.insertion_end + 1;  // no hold: retraction starts after the deepest point
  }
}

void find_cut_landmarks(const RunData& run, Segmentation& s) {
  const std::size_t end = s.hold_end > s.hold_begin ? s.hold_begin : s.insertion_end + 1;
  const std::vector<double> f = smooth_in_x(run, end, 0.05);
  double peak = 0.0;
  for (std::size_t i = 0; i < end; ++i) peak = std::max(peak, f[i]);
  const double drop = std::max(6.0 * s.noise_sigma_N, 0.08 * peak);
  // Puncture: the first local maximum followed by a drop of `drop` within 0.5 mm.
  double best = -1e9;
  std::size_t best_i = 0;
  for (std::size_t i = 0; i < end && !s.punctured; ++i) {
    if (run.x_mm[i] < 0.0) continue;
    // A drop counts within 0.5 mm of its peak; farther on, the search starts again here.
    const bool far_past_the_peak = run.x_mm[i] - run.x_mm[best_i] >= 0.5;
    if (f[i] > best || far_past_the_peak) {
      best = f[i];
      best_i = i;
    } else if (best - f[i] > drop) {
      s.punctured = true;
      s.x_pi_mm = run.x_mm[best_i];
    }
  }
  if (!s.punctured) {
    s.notes.push_back("no puncture found: the whole insertion is pre-cutting");
    s.x_pi_mm = s.x_c_mm = s.x_pf_mm = s.max_depth_mm;
    return;
  }
  // x_pf: where the force falls to the noise level for good after the puncture.
  const double floor = std::max(4.0 * s.noise_sigma_N, 0.03 * peak);
  s.x_pf_mm = s.max_depth_mm;
  for (std::size_t i = end; i-- > 0;) {
    if (run.x_mm[i] <= s.x_pi_mm) break;
    if (f[i] > floor) {
      s.x_pf_mm = run.x_mm[i];
      break;
    }
  }
  // x_c: the knee between the plateau (flat) and the straight unloading to zero at x_pf.
  double best_err = 1e300;
  s.x_c_mm = s.x_pi_mm;
  for (double xc = s.x_pi_mm + 0.2; xc < s.x_pf_mm - 0.2; xc += 0.05) {
    double fc = 0.0, n = 0.0;
    for (std::size_t i = 0; i < end; ++i) {
      if (std::abs(run.x_mm[i] - xc) < 0.1) fc += f[i], n += 1;
    }
    if (n == 0) continue;
    fc /= n;
    double err = 0.0;
    for (std::size_t i = 0; i < end; ++i) {
      const double x = run.x_mm[i];
      if (x < s.x_pi_mm + 0.1 || x > s.x_pf_mm) continue;
      const double fit = x < xc ? fc : fc * (s.x_pf_mm - x) / (s.x_pf_mm - xc);
      err += (f[i] - fit) * (f[i] - fit);
    }
    if (err < best_err) best_err = err, s.x_c_mm = xc;
  }
}

std::string step_note(const OffsetStep& step) {
  char text[128];
  std::snprintf(
      text, sizeof text,
      "an offset step of %+.1f mN at %.2f s: the puncture is found on the force without it",
      step.size_N * 1e3, step.t_s);
  return text;
}

Phase insertion_phase(const Segmentation& s, double x) {
  if (x < 0.0) return Phase::kApproach;
  if (!s.punctured || x < s.x_pi_mm) return Phase::kPrecut;
  if (x < s.x_c_mm) return Phase::kCutting;
  if (x < s.x_pf_mm) return Phase::kUnloading;
  return Phase::kRelaxation;
}

}  // namespace

const char* phase_name(Phase phase) {
  constexpr const char* kNames[] = {"approach",   "precut", "cutting",   "unloading",
                                    "relaxation", "hold",   "retraction"};
  return kNames[static_cast<int>(phase)];
}

double noise_sigma(const std::vector<double>& v, std::size_t begin, std::size_t end) {
  std::vector<double> d2;
  for (std::size_t i = begin + 1; i + 1 < end; ++i)
    d2.push_back(std::abs(v[i + 1] - 2.0 * v[i] + v[i - 1]));
  return median(d2) / 0.6745 / std::sqrt(6.0);
}

Segmentation detect_phases(const RunData& run) {
  Segmentation s;
  s.phase.assign(run.size(), Phase::kApproach);
  if (run.size() < 5) {
    s.notes.push_back("too few samples to segment");
    return s;
  }
  s.insertion_end = deepest_index(run);
  s.max_depth_mm = run.x_mm[s.insertion_end];
  s.noise_sigma_N = noise_sigma(run.force_N, 0, run.size());
  find_hold(run, s);
  // The puncture is found on the force less the sensor's own offset steps: a downward step
  // before the puncture was taken for its drop (draw 130043, 2026-11-28).
  s.offset_steps = find_offset_steps(run, s.noise_sigma_N);
  if (s.offset_steps.empty()) {
    find_cut_landmarks(run, s);
  } else {
    RunData corrected = run;
    corrected.force_N = without_steps(run, s.offset_steps);
    find_cut_landmarks(corrected, s);
    for (const OffsetStep& step : s.offset_steps) s.notes.push_back(step_note(step));
  }
  const std::size_t insertion_stop = s.hold_end > s.hold_begin ? s.hold_begin : s.insertion_end + 1;
  for (std::size_t i = 0; i < run.size(); ++i) {
    if (i < insertion_stop)
      s.phase[i] = insertion_phase(s, run.x_mm[i]);
    else if (i < s.hold_end)
      s.phase[i] = Phase::kHold;
    else
      s.phase[i] = Phase::kRetraction;
  }
  return s;
}

}  // namespace rig::model
