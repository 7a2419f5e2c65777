#include "stick_slip.hpp"

#include <algorithm>
#include <cmath>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& StickSlip::form_names() {
  static const std::vector<std::string> kNames = {"3 harmonics", "sine", "period following the speed"};
  return kNames;
}

std::vector<ParamSpec> StickSlip::shared_params() const {
  std::vector<ParamSpec> out = {{"period", "mm", 0.4, 0.05, 2.0}};
  if (form_ == kSine) out.push_back({"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5});
  if (form_ == kSpeedScaled) out.push_back({"speed_exponent", "1", 0.0, -1.0, 1.0});  // period x (v / 2 mm/s)^this
  return out;
}

std::vector<std::vector<double>> StickSlip::starts() const {
  std::vector<std::vector<double>> out;
  if (form_ == kSpeedScaled) {  // each eye's own phase: a coarser grid of periods finds the peak
    for (double period = 0.08; period <= 1.6; period *= 1.04) {
      for (const double exponent : {-0.3, 0.0, 0.3}) out.push_back({period, exponent});
    }
    return out;
  }
  for (double period = 0.08; period <= 1.6; period *= 1.02) out.push_back(form_ == kSine ? std::vector<double>{period, 1.0} : std::vector<double>{period});
  return out;
}

bool StickSlip::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (r->seg.punctured && r->seg.x_c_mm - r->seg.x_pi_mm > 0.5) return true;
  }
  why_not = "no run has a cutting phase longer than 0.5 mm";
  return false;
}

void StickSlip::design(const SampleView& s, const double* p, double* row) const {
  if (!s.cutting) {
    for (int c = 0; c < 2 * harmonics(); ++c) row[c] = 0.0;
    return;
  }
  fourier((s.x_mm - s.x_pi_mm) / period_mm(s.run->velocity_cmd_mm_s, p), harmonics(), row);
}

double StickSlip::period_mm(double velocity_mm_s, const double* p) const {
  if (form_ != kSpeedScaled) return p[0];
  constexpr double kReference_mm_s = 2.0;
  return p[0] * std::pow(std::max(std::abs(velocity_mm_s), 0.1) / kReference_mm_s, p[1]);
}

std::string StickSlip::evidence(const EvidenceInput& in) const {
  if (form_ == kSpeedScaled) {
    double slowest = 1e9, fastest = 0.0;  // [mm/s]
    for (const PreparedRun* r : in.runs) slowest = std::min(slowest, r->velocity_cmd_mm_s), fastest = std::max(fastest, r->velocity_cmd_mm_s);
    return format("tearing whose period follows the cutting speed: during the cutting phase the residual repeats every %.3f mm at 2 mm/s, "
                  "times (v / 2 mm/s)^%.2f (", in.shared[0], in.shared[1]) +
           format("%.3f mm at %.1f mm/s, %.3f mm at %.1f mm/s), each eye with its own amplitude and phase", period_mm(slowest, in.shared), slowest,
                  period_mm(fastest, in.shared), fastest) +
           honesty(in);
  }
  return std::string(form_ == kSine ? "sinusoidal tearing: " : "sawtooth-like tearing (3 harmonics): ") +
         format("during the cutting phase the residual repeats every %.3f mm from the puncture on (periodic tearing)", in.shared[0]) +
         honesty(in);
}

}  // namespace rig::model::effects
