#include "level_shifts.hpp"

#include <algorithm>
#include <cmath>

namespace rig::model {
namespace {

constexpr std::size_t kMinSide = 8;  // samples a side's line needs
constexpr double kStanding_mm_s =
    0.1;  // slower than this the carriage stands (servo settling is um/s)
constexpr double kSlopeShare =
    0.25;  // a slope in x "unchanged" within this share of the larger one
// A jump this soon after the carriage last stood [mm of advance] is the tissue's: on a soft
// mount the load comes back in a jump once the mount is taken up (220035, run 8), and a
// cornea loaded to its limit in a stop punctures as the blade sets off (run 6).
constexpr double kReload_mm = 0.6;
constexpr double kMotionChange_s = 0.1;  // a jump "as the carriage stops" is this close [s]:
                                         // the servo settles, and a rate law with it, in ~0.1 s
constexpr double kSpeedSpan_s = 0.01;    // the carriage's speed is taken over +- this [s] ...
constexpr double kSettled_mm_s = 0.3;    // ... and it stands under this (the pot's +-1 count
                                         // of 1.5 um over 20 ms reads as 0.15 mm/s)
constexpr double kRestSpan_s = 0.05;     // the carriage stands when it moves less than
                                         // kStanding_mm_s over this span [s]
// A drop that lands on the run's contact-free level and stays flat there is the blade let go
// (the cut through, or a soft mount snapping the tip forward: 220035), not the sensor.
constexpr double kFreeLevelSigmas = 6.0;
constexpr double kFreeLevelShare = 0.2;  // ... or within this share of the drop
// Slopes in x are compared over this much travel each side [mm] (at most kMaxSlopeWindow_s):
// over a 0.15 s window at 0.6 mm/s a slope's error is as large as a puncture's loss of
// stiffness on a soft mount, and the drop was taken for a step (290008, run 0).
constexpr double kSlopeReach_mm = 0.4;
constexpr double kMaxSlopeWindow_s = 1.0;

// Running sums of (1, u, u^2, f, u f, x, u x) over samples, u = t - t_0: a line over any
// index range in O(1). Entry k sums samples [0, k), so a range [lo, hi) is v[hi] - v[lo], up
// to hi = the run's size (until 2026-12-02 entry k held [0, k]: a range lost its first sample
// and one ending at the run's last sample read past the sums' end).
struct Sums {
  std::vector<double> n{0.0}, u{0.0}, uu{0.0}, f{0.0}, uf{0.0}, x{0.0}, ux{0.0};
  void add(double ui, double fi, double xi) {
    const auto back = [](const std::vector<double>& v) { return v.back(); };
    n.push_back(back(n) + 1.0), u.push_back(back(u) + ui), uu.push_back(back(uu) + ui * ui);
    f.push_back(back(f) + fi), uf.push_back(back(uf) + ui * fi), x.push_back(back(x) + xi),
        ux.push_back(back(ux) + ui * xi);
  }
};

// A least-squares line of y over samples [lo, hi), evaluated relative to time `at`.
struct Line {
  double value = 0.0;     // at `at`
  double slope = 0.0;     // per second
  double value_se = 0.0;  // in units of the noise sigma
  double slope_se = 0.0;  // ditto
  double x_slope = 0.0;   // the position's slope [mm/s]
  std::size_t count = 0;
};

Line line(const Sums& s, std::size_t lo, std::size_t hi, double at) {
  Line out;
  if (hi <= lo) return out;
  const auto range = [&](const std::vector<double>& v) { return v[hi] - v[lo]; };
  const double n = range(s.n), su = range(s.u) - n * at;
  const double suu = range(s.uu) - 2.0 * at * range(s.u) + n * at * at;
  const double sf = range(s.f), suf = range(s.uf) - at * sf, sx = range(s.x),
               sux = range(s.ux) - at * sx;
  const double centred = suu - su * su / n;
  out.count = hi - lo;
  if (centred <= 1e-12) return out;
  out.slope = (suf - su * sf / n) / centred;
  out.x_slope = (sux - su * sx / n) / centred;
  out.value = (sf - out.slope * su) / n;
  const double mean_u = su / n;
  out.value_se = std::sqrt(1.0 / n + mean_u * mean_u / centred);
  out.slope_se = 1.0 / std::sqrt(centred);
  return out;
}

struct Jump {
  std::size_t i = 0;
  double size = 0.0, z = 0.0;  // right - left [N]; |size| in standard errors
  Line left, right;
  Line left_wide, right_wide;  // reaching kSlopeReach_mm each side, for the slopes in x
  std::size_t l0 = 0, l1 = 0, r0 = 0, r1 = 0;  // the lines' samples: [l0, l1) and [r0, r1)
};

// The first sample at or after time `t` [s] (the run's size if none).
std::size_t first_at(const RunData& run, double t) {
  return static_cast<std::size_t>(std::lower_bound(run.t_s.begin(), run.t_s.end(), t) -
                                  run.t_s.begin());
}

// Whether the carriage stood less than kReload_mm of advance before sample `i`.
bool reloading(const RunData& run, std::size_t i) {
  for (std::size_t k = i, m = i; k > 0 && std::abs(run.x_mm[i] - run.x_mm[k]) < kReload_mm; --k) {
    while (m > 0 && run.t_s[k] - run.t_s[m] < kRestSpan_s) --m;
    if (run.t_s[k] - run.t_s[m] < kRestSpan_s) return false;  // the run's start
    if (std::abs(run.x_mm[k] - run.x_mm[m]) < kStanding_mm_s * (run.t_s[k] - run.t_s[m]))
      return true;
  }
  return false;
}

// Whether the carriage starts or stops within kMotionChange_s of sample `i`: its speed over
// +-kSpeedSpan_s is under kSettled_mm_s at some sample there and over it at another.
bool motion_changes_near(const RunData& run, std::size_t i) {
  const auto speed = [&](std::size_t k) {
    std::size_t lo = k, hi = k;
    while (lo > 0 && run.t_s[k] - run.t_s[lo] < kSpeedSpan_s) --lo;
    while (hi + 1 < run.size() && run.t_s[hi] - run.t_s[k] < kSpeedSpan_s) ++hi;
    const double dt = run.t_s[hi] - run.t_s[lo];
    return dt > 0.0 ? std::abs(run.x_mm[hi] - run.x_mm[lo]) / dt : 0.0;
  };
  bool standing = false, moving = false;
  for (std::size_t k = i; k > 0 && run.t_s[i] - run.t_s[k] <= kMotionChange_s; --k)
    (speed(k) < kSettled_mm_s ? standing : moving) = true;
  for (std::size_t k = i; k < run.size() && run.t_s[k] - run.t_s[i] <= kMotionChange_s; ++k)
    (speed(k) < kSettled_mm_s ? standing : moving) = true;
  return standing && moving;
}

// Where the force stands before the blade touches anything [N]: the first samples' mean.
double free_level(const std::vector<double>& force) {
  const std::size_t n = std::min<std::size_t>(force.size(), 4 * kMinSide);
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += force[i];
  return n > 0 ? sum / static_cast<double>(n) : 0.0;
}

// A drop onto the contact-free level, flat in x after it: the blade let go.
bool lets_go(const Jump& j, double sigma, double level) {
  if (j.size >= 0.0 || std::abs(j.right.x_slope) < kStanding_mm_s) return false;
  const double flat =
      4.0 * sigma * j.right.slope_se + 0.01 * std::abs(j.size) * std::abs(j.right.x_slope);
  const bool at_level = std::abs(j.right.value - level) <=
                        std::max(kFreeLevelSigmas * sigma, kFreeLevelShare * std::abs(j.size));
  return at_level && std::abs(j.right.slope) <= flat;
}

// Whether the jump is the sensor's (see the header) rather than the tissue's.
bool is_offset(const Jump& j, const RunData& run, double level, double sigma,
               const LevelShiftOptions& o) {
  // A change of slope in time makes the two lines disagree near it by up to about half that
  // change times the lines' reach (a kink at a stop, a speed change): a jump must dominate it.
  if (std::abs(j.size) < std::abs(j.right.slope - j.left.slope) * (o.gap_s + 0.5 * o.window_s))
    return false;
  const double vl = j.left.x_slope, vr = j.right.x_slope;
  const bool left_moves = std::abs(vl) >= kStanding_mm_s,
             right_moves = std::abs(vr) >= kStanding_mm_s;
  if (!left_moves && !right_moves) return true;  // at rest the tissue relaxes smoothly
  if (lets_go(j, sigma, level)) return false;
  if (left_moves && right_moves && vl * vr > 0.0) {
    if (reloading(run, j.i)) return false;
    // Moving on: a drop followed by a loss of stiffness (slope in x) is the tissue's, a
    // puncture or a release; a step keeps the slope.
    const Line& left = j.left_wide.count > 0 ? j.left_wide : j.left;
    const Line& right = j.right_wide.count > 0 ? j.right_wide : j.right;
    const double sl = left.slope / left.x_slope, sr = right.slope / right.x_slope;  // [N/mm]
    const double se =
        sigma * std::hypot(left.slope_se / left.x_slope, right.slope_se / right.x_slope);
    // A jump up is the tissue's only when its stiffness changes across it (130030: a rate law
    // that lets go at the puncture leaves a jump up onto the cutting plateau).
    if (j.size > 0.0)
      return std::abs(sr - sl) <= 4.0 * se + kSlopeShare * std::max(std::abs(sl), std::abs(sr));
    return sr >= sl - 4.0 * se - kSlopeShare * std::abs(sl);
  }
  // Starting (relaxed tissue reloads within a fraction of a mm), reversing or parking: the
  // tissue's. Stopping: the tissue's force stops rising and relaxes, it does not jump up,
  // unless the jump comes as the carriage stops: a rate law changes the force with the speed
  // at once (velocity weakening: 130011 jumped up by 23 mN as it stopped, and on with the
  // servo's settling). A sensor step that close to a stop is taken for the tissue's (120037:
  // two runs of nine, 30 and 10 ms before the stop); one further off stays a step.
  return j.size > 0.0 && vl >= kStanding_mm_s && !right_moves && !motion_changes_near(run, j.i);
}

// The jump's lines over kSlopeReach_mm of travel each side, kept only where the carriage
// moves on at the narrow lines' speed (within 30 %: no stop or reversal inside).
void widen(Jump& j, const Sums& s, const RunData& run, const LevelShiftOptions& o) {
  const double t = run.t_s[j.i], at = t - run.t_s.front();
  const auto same_speed = [](const Line& wide, const Line& narrow) {
    return std::abs(wide.x_slope - narrow.x_slope) <= 0.3 * std::abs(narrow.x_slope);
  };
  if (std::abs(j.left.x_slope) >= kStanding_mm_s) {
    const double reach =
        std::clamp(kSlopeReach_mm / std::abs(j.left.x_slope), o.window_s, kMaxSlopeWindow_s);
    const Line wide = line(s, first_at(run, t - o.gap_s - reach), first_at(run, t - o.gap_s), at);
    if (same_speed(wide, j.left)) j.left_wide = wide;
  }
  if (std::abs(j.right.x_slope) >= kStanding_mm_s) {
    const double reach =
        std::clamp(kSlopeReach_mm / std::abs(j.right.x_slope), o.window_s, kMaxSlopeWindow_s);
    const Line wide =
        line(s, first_at(run, t + o.gap_s + 1e-12), first_at(run, t + o.gap_s + reach + 1e-12), at);
    if (same_speed(wide, j.right)) j.right_wide = wide;
  }
}

// The median over samples [lo, hi) of the force less `from`'s line [N].
double median_off(const RunData& run, const std::vector<double>& force, std::size_t lo,
                  std::size_t hi, const Line& from, double at) {
  std::vector<double> d;
  for (std::size_t k = lo; k < hi; ++k)
    d.push_back(force[k] - (from.value + from.slope * (run.t_s[k] - run.t_s.front() - at)));
  if (d.empty()) return 0.0;
  std::nth_element(d.begin(), d.begin() + static_cast<std::ptrdiff_t>(d.size() / 2), d.end());
  return d[d.size() / 2];
}

// A level that changes and stays changed: most samples on each side stand off the other
// side's line by at least half the jump. A dip of a few ms inside one window (a rate law at a
// velocity blip of the servo: 320012, -90 mN for 6 ms) pulls a line, not the median.
bool persists(const Jump& j, const RunData& run, const std::vector<double>& force) {
  const double at = run.t_s[j.i] - run.t_s.front();
  const double right_off = median_off(run, force, j.r0, j.r1, j.left, at);
  const double left_off = median_off(run, force, j.l0, j.l1, j.right, at);
  const double half = 0.5 * j.size;
  return j.size > 0.0 ? right_off >= half && left_off <= -half
                      : right_off <= half && left_off >= -half;
}

// Jumps of `force` in `run` far above the noise, largest first, one per place.
std::vector<Jump> jumps(const RunData& run, const std::vector<double>& force, double sigma,
                        const LevelShiftOptions& o) {
  Sums s;
  const double t0 = run.t_s.front();
  for (std::size_t i = 0; i < run.size(); ++i) s.add(run.t_s[i] - t0, force[i], run.x_mm[i]);
  std::vector<Jump> out;
  for (std::size_t i = 0; i < run.size(); ++i) {
    const double t = run.t_s[i], at = t - t0;
    const std::size_t l0 = first_at(run, t - o.gap_s - o.window_s), l1 = first_at(run, t - o.gap_s);
    const std::size_t r0 = first_at(run, t + o.gap_s + 1e-12),
                      r1 = first_at(run, t + o.gap_s + o.window_s + 1e-12);
    if (l1 < l0 + kMinSide || r1 < r0 + kMinSide) continue;
    Jump j{i, 0.0, 0.0, line(s, l0, l1, at), line(s, r0, r1, at), {}, {}, l0, l1, r0, r1};
    j.size = j.right.value - j.left.value;
    const double se = sigma * std::hypot(j.left.value_se, j.right.value_se);
    j.z = std::abs(j.size) / std::max(se, 1e-12);
    if (std::abs(j.size) >= o.min_sigmas * sigma && j.z >= o.min_se) out.push_back(j);
  }
  // One jump per place: the largest, none other within a window and gap of it.
  std::sort(out.begin(), out.end(),
            [](const Jump& a, const Jump& b) { return std::abs(a.size) > std::abs(b.size); });
  std::vector<Jump> kept;
  for (const Jump& j : out) {
    const bool near = std::any_of(kept.begin(), kept.end(), [&](const Jump& k) {
      return std::abs(run.t_s[k.i] - run.t_s[j.i]) < o.window_s + o.gap_s;
    });
    if (!near) kept.push_back(j);
  }
  kept.erase(std::remove_if(kept.begin(), kept.end(),
                            [&](const Jump& j) { return !persists(j, run, force); }),
             kept.end());
  for (Jump& j : kept) widen(j, s, run, o);
  return kept;
}

}  // namespace

std::vector<OffsetStep> find_offset_steps(const RunData& run, double sigma_N,
                                          const LevelShiftOptions& o) {
  std::vector<OffsetStep> steps;
  if (run.size() < 4 * kMinSide || sigma_N <= 0.0) return steps;
  // The largest offset-like jump, then the next on the force without it (a step's lines
  // would show it again beside it), until none is left or too many are found.
  std::vector<double> force = run.force_N;
  while (steps.size() <= o.max_steps) {
    const std::vector<Jump> found = jumps(run, force, sigma_N, o);
    const double level = free_level(force);
    const auto step = std::find_if(found.begin(), found.end(), [&](const Jump& j) {
      const bool beside = std::any_of(steps.begin(), steps.end(), [&](const OffsetStep& k) {
        return std::abs(k.t_s - run.t_s[j.i]) < o.window_s + o.gap_s;
      });
      return !beside && is_offset(j, run, level, sigma_N, o);
    });
    if (step == found.end()) break;
    steps.push_back({step->i, run.t_s[step->i], step->size});
    for (std::size_t i = step->i; i < force.size(); ++i) force[i] -= step->size;
  }
  // A load cell's zero jumps now and then; a jump that repeats along the run (tears of the
  // tissue, a sawtooth ripple) is a process of the cut, not the sensor's.
  if (steps.size() > o.max_steps) steps.clear();
  std::sort(steps.begin(), steps.end(),
            [](const OffsetStep& a, const OffsetStep& b) { return a.index < b.index; });
  return steps;
}

std::vector<double> without_steps(const RunData& run, const std::vector<OffsetStep>& steps) {
  std::vector<double> f = run.force_N;
  for (const OffsetStep& s : steps) {
    for (std::size_t i = s.index; i < f.size(); ++i) f[i] -= s.size_N;
  }
  return f;
}

}  // namespace rig::model
