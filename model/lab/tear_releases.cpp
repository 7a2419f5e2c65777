#include "tear_releases.hpp"

#include <algorithm>
#include <cmath>

namespace rig::model {
namespace {

constexpr std::size_t kWindow = 5;  // samples each side of a drop (5 ms at 1 kHz)
constexpr double kSigmas = 6.0;     // a drop stands this far above the noise of its difference
// The puncture's own drop takes a few tenths of a millimetre past the puncture the data show
// (0.2 mm in the simulator); drops there are the puncture's, not tears (effect-free draw
// 360021: 16 such "releases" in 6 of 9 runs, every one within 0.05 mm of the puncture).
constexpr double kPastPuncture_mm = 0.3;
// Fewer drops than this in a run are events (the puncture, a slip), not tearing.
constexpr std::size_t kMinReleases = 3;

// Mean of force over [lo, hi) [N].
double mean_of(const std::vector<double>& f, std::size_t lo, std::size_t hi) {
  double sum = 0.0;
  for (std::size_t j = lo; j < hi; ++j) sum += f[j];
  return sum / static_cast<double>(hi - lo);
}

bool past_puncture(Phase p) {
  return p == Phase::kCutting || p == Phase::kUnloading || p == Phase::kRelaxation;
}

// Whether samples [lo, hi) are all past the puncture while inserting, the carriage moving.
bool cutting_through(const Segmentation& seg, const std::vector<double>& v, double slowest_mm_s,
                     std::size_t lo, std::size_t hi) {
  for (std::size_t j = lo; j < hi; ++j) {
    if (!past_puncture(seg.phase[j]) || v[j] < slowest_mm_s) return false;
  }
  return true;
}

// Drop between samples i and i+1 [N]: mean of kWindow samples up to i less that of kWindow after.
std::vector<double> drops(const RunData& run, const Segmentation& seg, const std::vector<double>& v,
                          double slowest_mm_s) {
  const std::size_t n = run.size();
  std::vector<double> out(n, 0.0);
  for (std::size_t i = kWindow; i + kWindow < n; ++i) {
    if (!cutting_through(seg, v, slowest_mm_s, i + 1 - kWindow, i + 1 + kWindow)) continue;
    out[i] =
        mean_of(run.force_N, i + 1 - kWindow, i + 1) - mean_of(run.force_N, i + 1, i + 1 + kWindow);
  }
  return out;
}

}  // namespace

TearReleases find_tear_releases(const RunData& run, const Segmentation& seg,
                                const std::vector<double>& velocity_mm_s, double insertion_mm_s) {
  constexpr double kSlowestShare = 0.25;  // of the insertion speed, over a drop's whole window
  TearReleases out;
  const std::size_t n = run.size();
  out.since_mm.assign(n, -1.0);
  if (!seg.punctured || n < 4 * kWindow || seg.phase.size() != n || velocity_mm_s.size() != n)
    return out;
  const double threshold =
      kSigmas * seg.noise_sigma_N * std::sqrt(2.0 / static_cast<double>(kWindow));
  const std::vector<double> d =
      drops(run, seg, velocity_mm_s, kSlowestShare * std::abs(insertion_mm_s));
  for (std::size_t i = kWindow; i + kWindow < n; ++i) {
    if (d[i] <= threshold || run.x_mm[i] < seg.x_pi_mm + kPastPuncture_mm) continue;
    const std::size_t lo = i - kWindow, hi = std::min(n, i + kWindow + 1);
    if (*std::max_element(d.begin() + static_cast<std::ptrdiff_t>(lo),
                          d.begin() + static_cast<std::ptrdiff_t>(hi)) > d[i])
      continue;
    if (!out.at.empty() && i - out.at.back() <= kWindow)
      continue;  // a tie within the window: the first
    out.at.push_back(i);
    out.drop_N.push_back(d[i]);
  }
  if (out.at.size() < kMinReleases) out.at.clear(), out.drop_N.clear();
  // Travel since the last release known at each sample: on through stops and the hold (a
  // held blade keeps the tear it built), none once the blade is withdrawn.
  std::size_t next = 0;
  double released_at_mm = 0.0;
  bool known = false;
  for (std::size_t j = 0; j < n; ++j) {
    while (next < out.at.size() && out.at[next] + kWindow < j)
      released_at_mm = run.x_mm[out.at[next] + 1], known = true, ++next;
    if (seg.phase[j] == Phase::kRetraction) known = false;
    if (known) out.since_mm[j] = std::max(0.0, run.x_mm[j] - released_at_mm);
  }
  return out;
}

}  // namespace rig::model
