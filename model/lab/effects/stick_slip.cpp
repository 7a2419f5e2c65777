#include "stick_slip.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& StickSlip::form_names() {
  static const std::vector<std::string> kNames = {"3 harmonics", "sine"};
  return kNames;
}

std::vector<ParamSpec> StickSlip::shared_params() const {
  std::vector<ParamSpec> out = {{"period", "mm", 0.4, 0.05, 2.0}};
  if (form_ == kSine) out.push_back({"harmonics", kFormLabelUnit, 1.0, 0.5, 1.5});
  return out;
}

std::vector<std::vector<double>> StickSlip::starts() const {
  std::vector<std::vector<double>> out;
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
  fourier((s.x_mm - s.x_pi_mm) / p[0], harmonics(), row);
}

std::string StickSlip::evidence(const EvidenceInput& in) const {
  return std::string(form_ == kSine ? "sinusoidal tearing: " : "sawtooth-like tearing (3 harmonics): ") +
         format("during the cutting phase the residual repeats every %.3f mm from the puncture on (periodic tearing)", in.shared[0]) +
         honesty(in);
}

}  // namespace rig::model::effects
