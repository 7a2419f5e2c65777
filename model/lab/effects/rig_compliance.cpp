#include "rig_compliance.hpp"

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& RigCompliance::form_names() {
  static const std::vector<std::string> kNames = {"linear", "polynomial", "stiffening",
                                                  "softening"};
  return kNames;
}

std::vector<ParamSpec> RigCompliance::shared_params() const {
  switch (form_) {
    case kLinear:
      return {{"c", "mm/N", 0.0, -0.5, 3.0}};
    // Up to 100 mm/N at no load: a mount that takes up a gap or a soft pad first (a few
    // tenths of a mm by ~10 mN, 250001) before it hardens.
    case kStiffening:
      return {{"c_0", "mm/N", 0.0, -0.5, 100.0}, {"F0", "N", 0.2, 0.005, 5.0}};
    // A mount that yields (a clamp slipping, a pad compressing): up to 10 mm/N at no load, the
    // yield force F0 from a fifth of a cut's force to far beyond it (then nearly linear).
    case kSoftening:
      return {{"c_0", "mm/N", 0.3, 0.0, 10.0}, {"F0", "N", 0.6, 0.05, 5.0}};
    default:
      return {{"c1", "mm/N", 0.0, -0.5, 3.0}, {"c2", "mm/N^2", 0.0, -10.0, 10.0}};
  }
}

std::vector<std::vector<double>> RigCompliance::starts() const {
  if (form_ == kSoftening) return softening_starts();
  if (form_ != kStiffening) return EffectTerm::starts();
  std::vector<std::vector<double>> out;  // c_0 = 0 leaves F0 without a gradient
  for (const double f0 : {0.05, 0.2, 1.0}) out.push_back({0.3, f0});
  // A soft mount that hardens: 30 mm/N at no load, 2-5 mm of lag at the cut's forces. The
  // eyes' puncture shifts and the baseline's depths hold a lag that large only once they
  // have moved with it, so these starts are fitted before one is chosen (fit_each_start).
  for (const double f0 : {0.15, 0.5}) out.push_back({30.0, f0});
  return out;
}

// A yield force just above the cut's forces (most of the lag by the peak), well above them
// (nearly linear) and between: each needs the eyes' puncture shifts moved with it, so each is
// fitted before one is kept, as the stiffening mount's are.
std::vector<std::vector<double>> RigCompliance::softening_starts() {
  std::vector<std::vector<double>> out;
  for (const double f0 : {0.35, 0.6, 1.5}) out.push_back({0.3, f0});
  return out;
}

bool RigCompliance::fit_each_start() const {
  return form_ == kStiffening || form_ == kSoftening;
}

// c F / (1 - F/F0) [mm] up to kYieldShare F0, then on along its tangent there (stiffness
// (1 - kYieldShare)^2 / c): finite and smooth for any force, whatever F0 the fit tries.
double RigCompliance::yielding_lag(double f, double c, double f0) {
  const double u = f / f0;
  if (u <= kYieldShare) return c * f / (1.0 - u);
  const double room = 1.0 - kYieldShare;
  return c * f0 * kYieldShare / room + c / (room * room) * (f - kYieldShare * f0);
}

double RigCompliance::lag(double force_N, const double* p) const {
  const double f = std::max(force_N, 0.0);
  switch (form_) {
    case kLinear:
      return p[0] * f;
    case kStiffening:
      return p[0] * f / (1.0 + f / p[1]);
    case kSoftening:
      return yielding_lag(f, p[0], p[1]);
    default:
      return p[0] * f + p[1] * f * f;
  }
}

// The tip lags by the lag of the force the mount carries: the measured force averaged over
// +-5 samples (PreparedRun::mean_force_N), not the sample itself, whose white noise would
// move the predicted tip by the noise times the compliance (2026-12-02, 290008).
double RigCompliance::x_shift(const SampleView& s, const double* p) const {
  if (s.inputs != nullptr) return lag(s.inputs->mean_force_N, p);
  if (s.run != nullptr && s.i < s.run->mean_force_N.size()) return lag(s.run->mean_force_N[s.i], p);
  return lag(s.force_N, p);
}

// The tip's deepest point is where it was when the carriage last stood at its front: backing
// off, the carriage first unloads the mount (by lag(F_front) - lag(F)) before the tip moves.
double RigCompliance::front_shift(const SampleView& s, const double* p) const {
  if (s.inputs != nullptr) return lag(s.inputs->front_force_N, p);
  if (s.run != nullptr && s.i < s.run->front_force_N.size())
    return lag(s.run->front_force_N[s.i], p);
  return lag(s.force_N, p);
}

std::string RigCompliance::evidence(const EvidenceInput& in) const {
  const double f = 0.2;  // a typical puncture force [N]
  const double* p = in.shared;
  const double at = lag(f, p);
  std::string mount;
  switch (form_) {
    case kLinear:
      mount = "linear mount: ";
      break;
    case kStiffening:
      mount = format("stiffening mount (stiffness doubles by %.3f N): ", p[1]);
      break;
    case kSoftening:  // (1 - u)^2 = 1/2 at u = 1 - sqrt(1/2)
      mount = format("softening mount (stiffness halves by %.3f N, yields towards %.3f N): ",
                     (1.0 - std::sqrt(0.5)) * p[1], p[1]);
      break;
    default:
      mount = p[1] < 0.0 ? "stiffening mount (polynomial): " : "softening mount (polynomial): ";
      break;
  }
  return mount +
         format("the tip lags the carriage by %.3f mm at %.1f N (mount stiffness about %.2f N/mm)",
                at, f, at > 1e-9 ? f / at : 0.0) +
         honesty(in);
}

}  // namespace rig::model::effects
