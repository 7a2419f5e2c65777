#include "stick_slip.hpp"

#include <algorithm>
#include <cmath>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& StickSlip::form_names() {
  static const std::vector<std::string> kNames = {
      "3 harmonics", "sine", "period following the speed", "tears released in the force",
      "period growing along the cut"};
  return kNames;
}

std::vector<ParamSpec> StickSlip::shared_params() const {
  if (form_ == kReleased)
    return {{"tear_length", "mm", 0.35, 0.05, 2.0},
            {"speed_exponent", "1", 0.0, -1.0, 1.0}};  // at 2 mm/s; x (v / 2 mm/s)^this
  if (form_ == kGrowing)
    return {{"period", "mm", 0.4, 0.05, 2.0},
            {"growth", "1/mm", 0.0, -0.5, 0.5}};  // at the puncture; x exp(this d)
  std::vector<ParamSpec> out = {{"period", "mm", 0.4, 0.05, 2.0}};
  if (form_ == kSine) out.push_back({"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5});
  if (form_ == kSpeedScaled)
    out.push_back({"speed_exponent", "1", 0.0, -1.0, 1.0});  // period x (v / 2 mm/s)^this
  return out;
}

std::vector<std::vector<double>> StickSlip::starts() const {
  std::vector<std::vector<double>> out;
  if (form_ == kReleased) {
    for (double length = 0.1; length <= 1.6; length *= 1.1) {
      for (const double exponent : {-0.3, 0.0, 0.3}) out.push_back({length, exponent});
    }
    return out;
  }
  if (form_ == kSpeedScaled) {  // each eye's own phase: a coarser grid of periods finds the peak
    for (double period = 0.08; period <= 1.6; period *= 1.04) {
      for (const double exponent : {-0.3, 0.0, 0.3}) out.push_back({period, exponent});
    }
    return out;
  }
  // No growth (g = 0) is the speed form at alpha = 0, so it is not a start here.
  if (form_ == kGrowing) {
    for (double period = 0.08; period <= 1.6; period *= 1.04) {
      for (const double growth : {-0.2, -0.1, 0.1, 0.2}) out.push_back({period, growth});  // [1/mm]
    }
    return out;
  }
  for (double period = 0.08; period <= 1.6; period *= 1.02)
    out.push_back(form_ == kSine ? std::vector<double>{period, 1.0} : std::vector<double>{period});
  return out;
}

bool StickSlip::applicable(const std::vector<const PreparedRun*>& runs,
                           std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (r->seg.punctured && r->seg.x_c_mm - r->seg.x_pi_mm > 0.5) return true;
  }
  why_not = "no run has a cutting phase longer than 0.5 mm";
  return false;
}

void StickSlip::design(const SampleView& s, const double* p, double* row) const {
  if (form_ == kReleased) {  // a ramp from -1 just after a release to +1 a tear's length on
    const double since_mm =
        s.cutting && s.i < s.run->tears.since_mm.size() ? s.run->tears.since_mm[s.i] : -1.0;
    row[0] = since_mm < 0.0
                 ? 0.0
                 : 2.0 * std::min(since_mm / period_mm(s.run->velocity_cmd_mm_s, p), 1.0) - 1.0;
    return;
  }
  if (!s.cutting) {
    for (int c = 0; c < 2 * harmonics(); ++c) row[c] = 0.0;
    return;
  }
  fourier(form_ == kGrowing ? growing_cycles(s.x_mm - s.x_pi_mm, p)
                            : (s.x_mm - s.x_pi_mm) / period_mm(s.run->velocity_cmd_mm_s, p),
          harmonics(), row);
}

// Tears cut `past_mm` beyond the puncture when the period is p exp(g d): the integral of
// 1 / (p exp(g d)) over d, (1 - exp(-g d)) / (g p) [cycles]; d / p where g is nearly 0.
double StickSlip::growing_cycles(double past_mm, const double* p) {
  const double growth_per_mm = p[1];
  if (std::abs(growth_per_mm * past_mm) < 1e-6) return past_mm / p[0];
  return -std::expm1(-growth_per_mm * past_mm) / (growth_per_mm * p[0]);
}

double StickSlip::period_mm(double velocity_mm_s, const double* p) const {
  if (form_ != kSpeedScaled && form_ != kReleased) return p[0];
  constexpr double kReference_mm_s = 2.0;
  return p[0] * std::pow(std::max(std::abs(velocity_mm_s), 0.1) / kReference_mm_s, p[1]);
}

int StickSlip::run_parameters(const PreparedRun& run) const {
  if (form_ != kReleased) return linear_columns();
  return run.tears.at.empty() ? 0 : 1;
}

// Released tears are a form only where the force let go often enough to show a tear's build.
bool StickSlip::identifiable(const EvidenceInput& fitted, std::string& why_not) const {
  constexpr std::size_t kMinReleases = 5;
  if (form_ != kReleased) return true;
  std::size_t releases = 0;
  for (const PreparedRun* r : fitted.runs) releases += r->tears.at.size();
  if (releases >= kMinReleases) return true;
  why_not = format("only %.0f releases of the force while cutting: too few to show tears building",
                   static_cast<double>(releases));
  return false;
}

std::string StickSlip::released_evidence(const EvidenceInput& in) const {
  std::vector<double> drops_mN, spacing_mm;
  std::size_t runs_with = 0;
  for (const PreparedRun* r : in.runs) {
    const TearReleases& t = r->tears;
    runs_with += t.at.empty() ? 0 : 1;
    for (std::size_t k = 0; k < t.at.size(); ++k) {
      drops_mN.push_back(1000.0 * t.drop_N[k]);
      if (k > 0) spacing_mm.push_back(r->data->x_mm[t.at[k]] - r->data->x_mm[t.at[k - 1]]);
    }
  }
  return format(
             "tears of any length, read off the force's releases: %.0f drops past the puncture in "
             "%.0f of %.0f runs (median %.1f mN, ",
             static_cast<double>(drops_mN.size()), static_cast<double>(runs_with),
             static_cast<double>(in.runs.size()), median(drops_mN)) +
         format(
             "median spacing %.3f mm); after each the force builds back over up to %.3f mm at 2 "
             "mm/s, times (v / 2 mm/s)^%.2f, each eye with its own amplitude",
             median(spacing_mm), in.shared[0], in.shared[1]) +
         honesty(in);
}

std::string StickSlip::evidence(const EvidenceInput& in) const {
  if (form_ == kReleased) return released_evidence(in);
  if (form_ == kGrowing) {
    double deepest_mm = 0.0;  // the longest cutting phase of these runs
    for (const PreparedRun* r : in.runs)
      deepest_mm = std::max(deepest_mm, r->seg.x_c_mm - r->seg.x_pi_mm);
    return format(
               "tearing whose period changes along the cut: %.3f mm at the puncture, times "
               "exp(%.3f/mm d), ",
               in.shared[0], in.shared[1]) +
           format("so %.3f mm at %.1f mm past it; each eye with its own amplitude and phase",
                  in.shared[0] * std::exp(in.shared[1] * deepest_mm), deepest_mm) +
           honesty(in);
  }
  if (form_ == kSpeedScaled) {
    double slowest = 1e9, fastest = 0.0;  // [mm/s]
    for (const PreparedRun* r : in.runs)
      slowest = std::min(slowest, r->velocity_cmd_mm_s),
      fastest = std::max(fastest, r->velocity_cmd_mm_s);
    return format(
               "tearing whose period follows the cutting speed: during the cutting phase the "
               "residual repeats every %.3f mm at 2 mm/s, "
               "times (v / 2 mm/s)^%.2f (",
               in.shared[0], in.shared[1]) +
           format(
               "%.3f mm at %.1f mm/s, %.3f mm at %.1f mm/s), each eye with its own amplitude and "
               "phase",
               period_mm(slowest, in.shared), slowest, period_mm(fastest, in.shared), fastest) +
           honesty(in);
  }
  return std::string(form_ == kSine ? "sinusoidal tearing: "
                                    : "sawtooth-like tearing (3 harmonics): ") +
         format(
             "during the cutting phase the residual repeats every %.3f mm from the puncture on "
             "(periodic tearing)",
             in.shared[0]) +
         honesty(in);
}

}  // namespace rig::model::effects
