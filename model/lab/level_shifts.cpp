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

// Running sums of (1, u, u^2, f, u f, x, u x) over samples, u = t - t_0: a line over any
// index range in O(1).
struct Sums {
  std::vector<double> n, u, uu, f, uf, x, ux;
  void add(double ui, double fi, double xi) {
    const auto back = [](const std::vector<double>& v) { return v.empty() ? 0.0 : v.back(); };
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
};

// Whether the jump is the sensor's (see the header) rather than the tissue's.
bool is_offset(const Jump& j, double sigma, const LevelShiftOptions& o) {
  // A change of slope in time makes the two lines disagree near it by up to about half that
  // change times the lines' reach (a kink at a stop, a speed change): a jump must dominate it.
  if (std::abs(j.size) < std::abs(j.right.slope - j.left.slope) * (o.gap_s + 0.5 * o.window_s))
    return false;
  const double vl = j.left.x_slope, vr = j.right.x_slope;
  const bool left_moves = std::abs(vl) >= kStanding_mm_s,
             right_moves = std::abs(vr) >= kStanding_mm_s;
  if (!left_moves && !right_moves) return true;  // at rest the tissue relaxes smoothly
  if (left_moves && right_moves && vl * vr > 0.0) {
    // Moving on: a drop followed by a loss of stiffness (slope in x) is the tissue's, a
    // puncture or a release; a step keeps the slope, and the tissue does not jump up.
    const double sl = j.left.slope / vl, sr = j.right.slope / vr;  // [N/mm]
    const double se = sigma * std::hypot(j.left.slope_se / vl, j.right.slope_se / vr);
    return j.size > 0.0 || sr >= sl - 4.0 * se - kSlopeShare * std::abs(sl);
  }
  // Starting (relaxed tissue reloads within a fraction of a mm), reversing or parking: the
  // tissue's. Stopping: the tissue's force stops rising and relaxes, it does not jump up.
  return j.size > 0.0 && vl >= kStanding_mm_s && !right_moves;
}

// Jumps of `force` in `run` far above the noise, largest first, one per place.
std::vector<Jump> jumps(const RunData& run, const std::vector<double>& force, double sigma,
                        const LevelShiftOptions& o) {
  Sums s;
  const double t0 = run.t_s.front();
  for (std::size_t i = 0; i < run.size(); ++i) s.add(run.t_s[i] - t0, force[i], run.x_mm[i]);
  const auto first_at = [&](double t) {
    return static_cast<std::size_t>(std::lower_bound(run.t_s.begin(), run.t_s.end(), t) -
                                    run.t_s.begin());
  };
  std::vector<Jump> out;
  for (std::size_t i = 0; i < run.size(); ++i) {
    const double t = run.t_s[i], at = t - t0;
    const std::size_t l0 = first_at(t - o.gap_s - o.window_s), l1 = first_at(t - o.gap_s);
    const std::size_t r0 = first_at(t + o.gap_s + 1e-12),
                      r1 = first_at(t + o.gap_s + o.window_s + 1e-12);
    if (l1 < l0 + kMinSide || r1 < r0 + kMinSide) continue;
    Jump j{i, 0.0, 0.0, line(s, l0, l1, at), line(s, r0, r1, at)};
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
    const auto step = std::find_if(found.begin(), found.end(), [&](const Jump& j) {
      const bool beside = std::any_of(steps.begin(), steps.end(), [&](const OffsetStep& k) {
        return std::abs(k.t_s - run.t_s[j.i]) < o.window_s + o.gap_s;
      });
      return !beside && is_offset(j, sigma_N, o);
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
