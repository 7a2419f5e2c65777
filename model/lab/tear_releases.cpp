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
// A drop this many sigmas of a one-sample difference is known from the sample after it
// alone, 4 samples before the windows show it: the simulator's tears let go within one
// sample, and at 3.7 mm/s a tear lasts ~130 samples, so 6 samples of lag mispredicted about
// half of its variance (draw 220013), 2 samples a tenth.
constexpr double kOneSampleSigmas = 8.0;

struct Release {
  std::size_t at = 0;     // the last sample before the drop
  std::size_t known = 0;  // the first sample whose prediction may use it
  double drop_N = 0.0;
};

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

// Releases the kWindow-sample means show: the largest drop within kWindow samples, known
// once the window after it has passed.
std::vector<Release> window_releases(const RunData& run, const Segmentation& seg,
                                     const std::vector<double>& v, double slowest_mm_s) {
  const std::size_t n = run.size();
  const double threshold =
      kSigmas * seg.noise_sigma_N * std::sqrt(2.0 / static_cast<double>(kWindow));
  const std::vector<double> d = drops(run, seg, v, slowest_mm_s);
  std::vector<Release> out;
  for (std::size_t i = kWindow; i + kWindow < n; ++i) {
    if (d[i] <= threshold || run.x_mm[i] < seg.x_pi_mm + kPastPuncture_mm) continue;
    const auto lo = d.begin() + static_cast<std::ptrdiff_t>(i - kWindow);
    if (*std::max_element(lo, d.begin() + static_cast<std::ptrdiff_t>(i + kWindow + 1)) > d[i])
      continue;
    out.push_back({i, i + kWindow + 1, d[i]});
  }
  return out;
}

// Releases one sample shows: a drop to the next sample of kOneSampleSigmas, known from the
// sample after the next on (its decision reads the two samples alone).
std::vector<Release> one_sample_releases(const RunData& run, const Segmentation& seg,
                                         const std::vector<double>& v, double slowest_mm_s) {
  const double threshold = kOneSampleSigmas * seg.noise_sigma_N * std::sqrt(2.0);
  std::vector<Release> out;
  for (std::size_t i = 0; i + 2 < run.size(); ++i) {
    const double drop = run.force_N[i] - run.force_N[i + 1];
    if (drop <= threshold || run.x_mm[i] < seg.x_pi_mm + kPastPuncture_mm) continue;
    if (cutting_through(seg, v, slowest_mm_s, i, i + 2)) out.push_back({i, i + 2, drop});
  }
  return out;
}

// One release for drops within kWindow samples of each other: the first, known as early as
// any of them shows it, the largest drop.
std::vector<Release> merged(std::vector<Release> events) {
  std::sort(events.begin(), events.end(),
            [](const Release& a, const Release& b) { return a.at < b.at; });
  std::vector<Release> out;
  for (const Release& e : events) {
    if (!out.empty() && e.at - out.back().at <= kWindow) {
      out.back().known = std::min(out.back().known, e.known);
      out.back().drop_N = std::max(out.back().drop_N, e.drop_N);
      continue;
    }
    out.push_back(e);
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
  const double slowest = kSlowestShare * std::abs(insertion_mm_s);
  std::vector<Release> events = window_releases(run, seg, velocity_mm_s, slowest);
  const std::vector<Release> sudden = one_sample_releases(run, seg, velocity_mm_s, slowest);
  events.insert(events.end(), sudden.begin(), sudden.end());
  for (const Release& r : merged(std::move(events))) {
    out.at.push_back(r.at), out.known.push_back(r.known), out.drop_N.push_back(r.drop_N);
  }
  if (out.at.size() < kMinReleases) out.at.clear(), out.known.clear(), out.drop_N.clear();
  // Travel since the last release known at each sample: on through stops and the hold (a
  // held blade keeps the tear it built), none once the blade is withdrawn.
  std::size_t next = 0;
  double released_at_mm = 0.0;
  bool known = false;
  for (std::size_t j = 0; j < n; ++j) {
    while (next < out.at.size() && out.known[next] <= j)
      released_at_mm = run.x_mm[out.at[next] + 1], known = true, ++next;
    if (seg.phase[j] == Phase::kRetraction) known = false;
    if (known) out.since_mm[j] = std::max(0.0, run.x_mm[j] - released_at_mm);
  }
  return out;
}

}  // namespace rig::model
