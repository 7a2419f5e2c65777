#include "shaft_friction.hpp"

#include <algorithm>

#include "effect_util.hpp"

namespace rig::model::effects {

bool ShaftFriction::applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const {
  for (const PreparedRun* r : runs) {
    if (r->seg.punctured) return true;
  }
  why_not = "no run was punctured";
  return false;
}

namespace {

// (1 - exp(-k L)) / k, equal to L at k = 0 [mm].
double effective_length(double length_mm, double kappa) {
  // expm1 stays accurate for tiny k L, so the derivative in k survives near k = 0.
  if (kappa == 0.0) return length_mm;
  return -std::expm1(-kappa * length_mm) / kappa;
}

}  // namespace

double ShaftFriction::add(const SampleView& s, const double* p, double /*force_N*/) const {
  if (s.inserted_mm <= 0.0) return 0.0;
  // Friction opposes the motion: the phase gives its direction (a velocity estimate smears
  // the sign flip at the turnaround, which takes about a millisecond).
  double direction = s.phase == Phase::kRetraction ? -1.0 : (s.phase == Phase::kHold ? 0.0 : 1.0);
  if (s.i == s.run->seg.insertion_end) direction = 0.0;  // the turnaround itself: at rest
  return p[0] * effective_length(s.inserted_mm, p[1]) * direction;
}

std::string ShaftFriction::evidence(const EvidenceInput& in) const {
  double deepest = 0.0;  // inserted length at the deepest point, from the detected puncture
  for (const PreparedRun* r : in.runs) deepest = std::max(deepest, r->seg.max_depth_mm - r->seg.x_pi_mm);
  const double at_depth = in.shared[0] * effective_length(deepest, in.shared[1]);
  return format("after the puncture the residual grows %.4f N/mm with inserted blade length and reverses sign on "
                "retraction (%.3f N at %.1f mm inserted)", in.shared[0], at_depth, deepest);
}

}  // namespace rig::model::effects
