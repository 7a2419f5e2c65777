#include "shaft_friction.hpp"

#include <algorithm>
#include <cmath>

#include "effect_util.hpp"

namespace rig::model::effects {

ShaftFriction::ShaftFriction(int form) : FamilyTerm(form_names(), form) {}

const std::vector<std::string>& ShaftFriction::form_names() {
  static const std::vector<std::string> kNames = {
      "coulomb",    "saturating",       "viscous",      "coulomb + viscous",
      "asymmetric", "static breakaway", "held at rest", "presliding"};
  return kNames;
}

std::vector<ParamSpec> ShaftFriction::shared_params() const {
  const ParamSpec mu{"mu", "N/mm", 0.0, -0.1, 0.1};
  const ParamSpec eta{"eta", "N s/mm^2", 0.0, -0.05, 0.05};
  switch (form_) {
    case kCoulomb:
      return {mu};
    case kHeldAtRest:
      return {
          {"mu_held", "N/mm", 0.0, -0.1, 0.1}};  // its own name: a saved model reloads in this form
    case kViscous:
      return {eta};
    case kCoulombViscous:
      return {mu, eta};
    case kAsymmetric:
      return {{"mu_in", "N/mm", 0.0, -0.1, 0.1}, {"mu_out", "N/mm", 0.0, -0.1, 0.1}};
    case kBreakaway:
      return {mu, {"mu_s", "N/mm", 0.0, -0.1, 0.2}, {"v_s", "mm/s", 0.3, 0.01, 5.0}};
    case kPresliding:
      return {{"mu_grip", "N/mm", 0.0, -0.1, 0.1}, {"grip_mm", "mm", 0.1, 0.003, 2.0}};
    default:
      return {mu, {"kappa", "1/mm", 0.0, -0.3, 3.0}};
  }
}

std::vector<std::vector<double>> ShaftFriction::starts() const {
  std::vector<std::vector<double>>
      out;  // the friction needs a start off zero, or the speed or distance has no gradient
  if (form_ == kBreakaway) {
    for (const double v_s : {0.05, 0.2, 1.0}) out.push_back({0.003, 0.005, v_s});
  } else if (form_ == kPresliding) {
    for (const double grip : {0.02, 0.1, 0.5}) out.push_back({0.005, grip});
  } else {
    return EffectTerm::starts();
  }
  return out;
}

bool ShaftFriction::applicable(const std::vector<const PreparedRun*>& runs,
                               std::string& why_not) const {
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

// Friction opposes the motion: the phase gives its direction (a velocity estimate smears the
// sign flip at the turnaround, which takes about a millisecond). At rest - the hold at depth,
// a stop on the way in (hold_s counts its time), the turnaround - sliding friction is gone.
double motion_direction(const SampleView& s) {
  if (s.i == s.run->seg.insertion_end) return 0.0;
  if (s.phase == Phase::kRetraction) return -1.0;
  return s.phase == Phase::kHold || s.hold_s > 0.0 ? 0.0 : 1.0;
}

// Friction that stays loaded at rest (presliding, as in Dahl's and LuGre's models): a stop
// keeps the force of the last slide; only the retraction reverses it.
double held_direction(const SampleView& s) {
  return s.phase == Phase::kRetraction ? -1.0 : 1.0;
}

// Presliding as an elastic-plastic grip (a Jenkins element: a spring until it slips): the
// tissue holds the shaft like a spring, so the friction follows the blade's travel back from
// its furthest point d = front - x linearly, from +1 (pulled in) to -1 at d = grip, and slides
// beyond. A stop keeps the load; a servo settling back some µm at the hold, or the first part
// of a retraction, turn it only partly.
double gripped_direction(const SampleView& s, double grip_mm) {
  const double front_mm = s.inputs != nullptr ? s.inputs->front_mm : s.run->front_mm[s.i];
  const double back_mm = std::max(0.0, front_mm - s.x_mm);
  return 1.0 - 2.0 * std::min(1.0, back_mm / grip_mm);
}

}  // namespace

double ShaftFriction::add(const SampleView& s, const double* p, double /*force_N*/) const {
  const double length = s.inserted_mm;
  if (length <= 0.0) return 0.0;
  const double dir = motion_direction(s);
  switch (form_) {
    case kCoulomb:
      return p[0] * length * dir;
    case kViscous:
      return p[0] * length * s.velocity_mm_s;
    case kCoulombViscous:
      return (p[0] * dir + p[1] * s.velocity_mm_s) * length;
    case kAsymmetric:
      return length * (dir > 0.0 ? p[0] : (dir < 0.0 ? -p[1] : 0.0));
    case kBreakaway:
      return length * dir * (p[0] + p[1] * std::exp(-std::abs(s.velocity_mm_s) / p[2]));
    case kHeldAtRest:
      return p[0] * length * held_direction(s);
    case kPresliding:
      return p[0] * length * gripped_direction(s, p[1]);
    default:
      return p[0] * effective_length(length, p[1]) * dir;
  }
}

namespace {

// The chosen form and its fitted values in words. deepest: inserted length at the deepest point
// from the detected puncture [mm]; speed: the fastest run's cutting speed [mm/s].
std::string form_in_words(ShaftFriction::Form form, const double* p, double deepest, double speed) {
  std::string text;
  switch (form) {
    case ShaftFriction::kCoulomb:
      text = format(
          "coulomb friction: %.4f N per mm inserted, reversing on retraction (%.3f N at %.1f mm)",
          p[0], p[0] * deepest, deepest);
      break;
    case ShaftFriction::kViscous:
      text = format(
          "viscous friction: %.4f N per mm inserted per mm/s (%.3f N at %.1f mm and %.1f mm/s)",
          p[0], p[0] * deepest * speed, deepest, speed);
      break;
    case ShaftFriction::kCoulombViscous:
      text = format(
                 "viscous + coulomb friction: %.4f N/mm inserted plus %.4f N/mm per mm/s (%.3f N "
                 "at %.1f mm",
                 p[0], p[1], (p[0] + p[1] * speed) * deepest, deepest) +
             format(" and %.1f mm/s)", speed);
      break;
    case ShaftFriction::kHeldAtRest:
      text = format(
          "coulomb friction held at rest: %.4f N per mm inserted, kept through stops and the hold, "
          "reversing on retraction (%.3f N at %.1f mm)",
          p[0], p[0] * deepest, deepest);
      break;
    case ShaftFriction::kPresliding:
      text = format(
          "presliding friction (elastic-plastic grip): %.4f N per mm inserted, held through stops "
          "and the hold, reversed over %.3f mm as the blade backs off "
          "(%.3f N at %.1f mm)",
          p[0], p[1], p[0] * deepest, deepest);
      break;
    case ShaftFriction::kAsymmetric:
      text = format(
          "direction-asymmetric friction: %.4f N/mm inserting, %.4f N/mm retracting (%.3f N at "
          "%.1f mm inserting)",
          p[0], p[1], p[0] * deepest, deepest);
      break;
    case ShaftFriction::kBreakaway:
      text = format(
                 "coulomb friction with static breakaway: %.4f N/mm sliding, %.4f N/mm more at "
                 "rest, fading by %.2f mm/s (%.3f N sliding at ",
                 p[0], p[1], p[2], p[0] * deepest) +
             format("%.1f mm)", deepest);
      break;
    default:
      text = format(
          "saturating friction: the residual grows %.4f N/mm with inserted blade length "
          "(saturating at %.2f /mm) and reverses sign on "
          "retraction (%.3f N at %.1f mm inserted)",
          p[0], p[1], p[0] * effective_length(deepest, p[1]), deepest);
  }
  return text;
}

}  // namespace

std::string ShaftFriction::evidence(const EvidenceInput& in) const {
  double deepest = 0.0;  // inserted length at the deepest point, from the detected puncture [mm]
  double speed = 0.0;    // the fastest run's cutting speed [mm/s]
  for (const PreparedRun* r : in.runs) {
    deepest = std::max(deepest, r->seg.max_depth_mm - r->seg.x_pi_mm);
    speed = std::max(speed, r->velocity_cmd_mm_s);
  }
  return form_in_words(static_cast<Form>(form_), in.shared, deepest, speed) + honesty(in);
}

}  // namespace rig::model::effects
