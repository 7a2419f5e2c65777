#include "prepared_run.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>

#include "grid_line.hpp"

namespace rig::model {

std::optional<double> PreparedRun::covariate(const std::string& key, std::size_t i) const {
  if (const auto at = derived.find(key); at != derived.end()) return at->second;
  if (const Channel* channel = data->channel(key)) return channel->values[i];
  if (const auto at = metadata_numbers.find(key); at != metadata_numbers.end()) return at->second;
  return std::nullopt;
}

namespace {

void derive_velocity(PreparedRun& p) {
  const RunData& r = *p.data;
  p.velocity_mm_s.assign(r.size(), 0.0);
  constexpr double kHalfWindow_s = 0.01;
  std::size_t lo = 0, hi = 0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    while (lo < i && r.t_s[lo] < r.t_s[i] - kHalfWindow_s) ++lo;
    while (hi + 1 < r.size() && r.t_s[hi + 1] <= r.t_s[i] + kHalfWindow_s) ++hi;
    const double dt = r.t_s[hi] - r.t_s[lo];
    p.velocity_mm_s[i] = dt > 1e-9 ? (r.x_mm[hi] - r.x_mm[lo]) / dt : 0.0;
  }
}

double measured_insertion_velocity(const PreparedRun& p) {
  std::vector<double> v;
  for (std::size_t i = 0; i < p.seg.insertion_end; ++i) {
    if (p.data->x_mm[i] > 0.5 && p.data->x_mm[i] < p.seg.max_depth_mm - 0.5)
      v.push_back(p.velocity_mm_s[i]);
  }
  return v.empty() ? 1.0 : median(std::move(v));
}

// Stops on the way in (a protocol's pauses before the deepest point, in tissue): the tissue
// relaxes in them as in the hold at depth, so hold_s counts the time since each stop began.
// A stop is where the position, averaged over +-50 ms (a potentiometer's noise would make a
// +-10 ms velocity jitter by tenths of mm/s), moves slower than half the insertion velocity
// for at least 0.2 s.
void derive_pauses(PreparedRun& p) {
  constexpr double kHalfWindow_s = 0.05, kMinStop_s = 0.2;
  const RunData& r = *p.data;
  const std::size_t end = std::min(
      p.seg.hold_end > p.seg.hold_begin ? p.seg.hold_begin : p.seg.insertion_end, r.size());
  const double slow = 0.5 * std::max(std::abs(p.velocity_cmd_mm_s), 0.05);  // [mm/s]
  p.reload_mm.assign(r.size(), -1.0);
  p.stop_length_s.assign(r.size(), 0.0);
  std::size_t lo = 0, hi = 0, stop_begin = end, last_stop_end = end;
  double last_stop_s = 0.0;
  auto close_stop = [&](std::size_t stop_end) {
    if (stop_begin < stop_end && r.t_s[stop_end - 1] - r.t_s[stop_begin] >= kMinStop_s) {
      for (std::size_t k = stop_begin; k < stop_end; ++k)
        p.hold_s[k] = r.t_s[k] - r.t_s[stop_begin];
      last_stop_end = stop_end;
      last_stop_s = r.t_s[stop_end - 1] - r.t_s[stop_begin];
    }
    stop_begin = end;
  };
  for (std::size_t i = 0; i < end; ++i) {
    while (lo < i && r.t_s[lo] < r.t_s[i] - kHalfWindow_s) ++lo;
    while (hi + 1 < r.size() && r.t_s[hi + 1] <= r.t_s[i] + kHalfWindow_s) ++hi;
    const std::size_t half = (hi - lo) / 2;  // velocity of the window's two halves' means
    double first = 0.0, second = 0.0;
    for (std::size_t k = lo; k < lo + half; ++k) first += r.x_mm[k];
    for (std::size_t k = hi + 1 - half; k <= hi; ++k) second += r.x_mm[k];
    const double dt = r.t_s[hi + 1 - half + half / 2] - r.t_s[lo + half / 2];
    const bool stopped = half > 0 && dt > 1e-9 && r.x_mm[i] > 0.0 &&
                         std::abs(second - first) / static_cast<double>(half) / dt < slow;
    if (stopped && stop_begin == end) stop_begin = i;
    if (!stopped && stop_begin != end) close_stop(i);
    if (stop_begin == end && last_stop_end < i) {  // moving on after a stop: the tissue reloads
      p.reload_mm[i] = std::max(0.0, p.front_mm[i] - p.front_mm[last_stop_end]);
      p.stop_length_s[i] = last_stop_s;
    }
  }
  close_stop(end);
}

// The measured force when the carriage was last at its front [N]: while it advances or is
// held there, the force now; once it backs off, the force it left the front with. Both
// averaged over +-5 samples (as the front is). A mount's tip stays behind the carriage by
// the lag of that force, so this is where the tip's own front is (rig_compliance). The
// +-5-sample mean is kept too (mean_force_N): a soft mount's lag, read off the force sample
// by sample, moves the predicted tip by the load cell's white noise times the mount's
// compliance (on draw 290008, 1.5 mN of noise at the fitted 4.6 mm/N by the peak force,
// 0.24 N: 0.007 mm of tip), noise the prediction adds to the measured noise.
void derive_front_force(PreparedRun& p) {
  constexpr double kAtFront_mm = 0.01;  // the front's own tolerance for a noisy held position
  const RunData& r = *p.data;
  p.front_force_N.assign(r.size(), 0.0);
  p.mean_force_N.assign(r.size(), 0.0);
  double deepest_mean = -1e9;
  double at_front = 0.0;
  for (std::size_t i = 0; i < r.size(); ++i) {
    const std::size_t lo = i >= 5 ? i - 5 : 0;
    const std::size_t hi = std::min(r.size(), i + 6);
    double x = 0.0, f = 0.0;
    for (std::size_t j = lo; j < hi; ++j) x += r.x_mm[j], f += r.force_N[j];
    x /= static_cast<double>(hi - lo);
    f /= static_cast<double>(hi - lo);
    p.mean_force_N[i] = f;
    deepest_mean = std::max(deepest_mean, x);
    if (x >= deepest_mean - kAtFront_mm) at_front = f;
    p.front_force_N[i] = at_front;
  }
}

// Last step of prepare_run: every per-sample input final, copy them side by side.
void pack_inputs(PreparedRun& p, const std::vector<double> (&grid_cycles)[2]) {
  const RunData& r = *p.data;
  p.inputs.resize(r.size());
  for (std::size_t i = 0; i < r.size(); ++i) {
    SampleInputs& in = p.inputs[i];
    in = {r.x_mm[i],     r.t_s[i],   r.force_N[i],   p.velocity_mm_s[i], p.hold_s[i],
          p.front_mm[i], {0.0, 0.0}, p.seg.phase[i], p.front_force_N[i], p.mean_force_N[i]};
    for (int k = 0; k < 2; ++k)
      in.grid_cycles[k] = i < grid_cycles[k].size() ? grid_cycles[k][i] : std::nan("");
  }
  const std::size_t parked = std::min<std::size_t>(r.size(), 20);
  for (std::size_t i = 0; i < parked; ++i) p.parked_mm += r.x_mm[i] / static_cast<double>(parked);
}

}  // namespace

std::size_t jittered_row(std::size_t k, std::size_t lo, std::size_t hi, std::size_t n) {
  if (hi <= lo + 1) return lo;
  // splitmix64 of (stratum, run length): a fixed pseudo-random place in [lo, hi).
  std::uint64_t z =
      (static_cast<std::uint64_t>(k) + 1) * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(n);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return lo + static_cast<std::size_t>(z % (hi - lo));
}

namespace {

// Per sample: the blade's front (deepest point so far, smoothed), the time in the hold and the
// blade length inserted past the puncture [mm].
void derive_front_hold_and_inserted(PreparedRun& p) {
  const RunData& run = *p.data;
  p.hold_s.assign(run.size(), 0.0);
  p.inserted_mm.assign(run.size(), 0.0);
  p.front_mm.assign(run.size(), 0.0);
  double front = -1e9;
  double deepest = -1e9;  // of the raw samples, for the inserted length
  for (std::size_t i = 0; i < run.size(); ++i) {
    // The front is the deepest point of x averaged over +-5 samples: the maximum of raw
    // noisy samples would sit above a held position by ~2 sigma of the potentiometer.
    const std::size_t lo = i >= 5 ? i - 5 : 0;
    const std::size_t hi = std::min(run.size(), i + 6);
    double mean = 0.0;
    for (std::size_t j = lo; j < hi; ++j) mean += run.x_mm[j];
    front = std::max(front, mean / static_cast<double>(hi - lo));
    p.front_mm[i] = std::max(front, run.x_mm[i] - 0.01);
    deepest = std::max(deepest, run.x_mm[i]);
    // In the hold: time since it began; after it (retraction): its whole length, since the
    // withdrawn tissue stays as relaxed as the hold left it.
    if (p.seg.phase[i] == Phase::kHold) p.hold_s[i] = run.t_s[i] - run.t_s[p.seg.hold_begin];
    if (p.seg.phase[i] == Phase::kRetraction && p.seg.hold_end > p.seg.hold_begin) {
      p.hold_s[i] = run.t_s[p.seg.hold_end - 1] - run.t_s[p.seg.hold_begin];
    }
    if (p.seg.punctured)
      p.inserted_mm[i] = std::max(0.0, std::min(run.x_mm[i], deepest) - p.seg.x_pi_mm);
  }
}

}  // namespace

PreparedRun prepare_run(const RunData& run, std::size_t max_fit_rows) {
  PreparedRun p;
  p.data = &run;
  p.seg = detect_phases(run);
  derive_velocity(p);
  derive_front_hold_and_inserted(p);
  std::size_t first = 0;
  while (first < run.size() && run.x_mm[first] < 0.0) ++first;
  for (std::size_t i = first; i < run.size(); ++i) p.analysed.push_back(i);
  // One row per stride, at a jittered place in it (below): an even stride of a 1 kHz run is
  // often a whole number of mains cycles (16,000 samples / 800 rows = 20 ms = one 50 Hz
  // cycle), and rows at one phase see the pick-up as a constant.
  const std::size_t n = p.analysed.size();
  const std::size_t stride = std::max<std::size_t>(1, n / std::max<std::size_t>(max_fit_rows, 1));
  for (std::size_t lo = 0; lo < n; lo += stride)
    p.fit_rows.push_back(p.analysed[jittered_row(lo / stride, lo, std::min(n, lo + stride), n)]);
  std::vector<double> tracked[2];
  for (int k = 0; k < 2; ++k) {
    p.grid_hz[k] = grid_line_hz(run.t_s, run.force_N, first, run.size(), k == 0 ? 50.0 : 60.0);
    tracked[k] = grid_cycles(run.t_s, run.force_N, first, p.grid_hz[k]);
  }
  p.iop_known = run.number("iop_mmHg").has_value();
  p.iop_mmHg = run.number("iop_mmHg").value_or(15.0);
  if (!p.iop_known)
    p.warnings.push_back(
        run.source +
        ": no iop_mmHg: the model is evaluated at 15 mmHg and IOP analyses leave this run out");
  p.velocity_known = run.number("velocity_mm_s").has_value();
  p.velocity_cmd_mm_s = run.number("velocity_mm_s").value_or(measured_insertion_velocity(p));
  if (!p.velocity_known)
    p.warnings.push_back(run.source +
                         ": no velocity_mm_s: the measured insertion velocity is used");
  derive_pauses(p);
  derive_front_force(p);
  p.tears = find_tear_releases(run, p.seg, p.velocity_mm_s, p.velocity_cmd_mm_s);
  pack_inputs(p, tracked);
  pack_fit_rows(p);
  for (const auto& [key, text] : run.meta) {
    if (const auto value = run.number(key)) p.metadata_numbers[key] = *value;
  }
  for (const auto& note : p.seg.notes) p.warnings.push_back(run.source + ": " + note);
  return p;
}

void pack_fit_rows(PreparedRun& run) {
  run.fit_inputs.resize(run.fit_rows.size());
  for (std::size_t n = 0; n < run.fit_rows.size(); ++n)
    run.fit_inputs[n] = run.inputs.at(run.fit_rows[n]);
}

RowBudget row_budget(std::size_t runs, std::size_t samples) {
  constexpr std::size_t kFitRows = 10000, kMinFitRows = 100, kMaxFitRows = 800, kScored = 250000;
  RowBudget b;
  runs = std::max<std::size_t>(runs, 1);
  b.fit_rows_per_run = std::clamp(kFitRows / runs, kMinFitRows, kMaxFitRows);
  if (samples > kScored) b.scored_per_run = kScored / runs;
  return b;
}

void thin_analysed(PreparedRun& run, std::size_t max_rows) {
  if (max_rows == 0 || run.analysed.size() <= max_rows) return;
  std::vector<std::size_t> kept;
  kept.reserve(max_rows);
  const std::size_t n = run.analysed.size();
  for (std::size_t k = 0; k < max_rows; ++k)
    kept.push_back(run.analysed[jittered_row(k, k * n / max_rows, (k + 1) * n / max_rows, n)]);
  run.analysed = std::move(kept);
}

void add_run_order(std::vector<PreparedRun>& runs) {
  std::map<std::string, std::vector<std::pair<std::string, PreparedRun*>>> sessions;
  for (PreparedRun& run : runs) {
    const auto started = run.data->text("started_at");
    if (!started || started->empty()) return;
    const auto session = run.data->text("session");
    sessions[session ? *session : started->substr(0, 10)].emplace_back(*started, &run);
  }
  for (auto& [session, members] : sessions) {
    std::stable_sort(members.begin(), members.end(),
                     [](const auto& a, const auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < members.size(); ++k)
      members[k].second->derived["run_order"] = static_cast<double>(k + 1);
  }
}

}  // namespace rig::model
