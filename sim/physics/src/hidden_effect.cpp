#include "rig/sim/hidden_effect.hpp"

#include <algorithm>
#include <array>
#include <charconv>

#include "rig/sim/active_effects.hpp"

namespace rig::sim {
namespace {

struct EffectInfo {
  EffectKind kind;
  const char* name;
  std::vector<std::string> forms;  // first = default
};

const std::array<EffectInfo, kEffectKindCount>& catalogue() {
  static const std::array<EffectInfo, kEffectKindCount> kInfo{{
      {EffectKind::kRateDependence,
       "rate_dependence",
       {"carreau", "power_cutoff", "logarithmic", "exp_saturating"}},
      {EffectKind::kIopStiffness, "iop_stiffness", {"saturating", "prestress", "recruitment"}},
      {EffectKind::kShaftFriction, "shaft_friction", {"coulomb_viscous", "stribeck", "dahl"}},
      {EffectKind::kRigCompliance,
       "rig_compliance",
       {"hardening", "softening", "backlash", "stiffening"}},
      {EffectKind::kSensorDrift, "sensor_drift", {"thermal", "random_walk", "step", "warmup"}},
      {EffectKind::kSpatialRipple, "spatial_ripple", {"lead_error", "load_modulated", "sawtooth"}},
      {EffectKind::kMainsInterference,
       "mains_interference",
       {"drifting", "harmonics", "motor_gated", "60hz"}},
      {EffectKind::kStickSlip, "stick_slip", {"aperiodic", "growing", "velocity_weakening"}},
      {EffectKind::kStressRelaxation,
       "stress_relaxation",
       {"fung_qlv", "prony3", "mittag_leffler"}},
      {EffectKind::kCovariate, "covariate", {"sigmoid", "hinge_all", "puncture_shift"}},
  }};
  return kInfo;
}

std::string_view take_until(std::string_view& rest, char separator) {
  const auto at = rest.find(separator);
  const std::string_view head = rest.substr(0, at);
  rest = at == std::string_view::npos ? std::string_view{} : rest.substr(at + 1);
  return head;
}

}  // namespace

std::string effect_name(EffectKind kind) {
  return catalogue()[static_cast<int>(kind)].name;
}

std::vector<std::string> effect_forms(EffectKind kind) {
  return catalogue()[static_cast<int>(kind)].forms;
}

std::optional<HiddenEffect> parse_hidden_effect(std::string_view spec, std::string& error) {
  HiddenEffect effect;
  std::string_view rest = spec;
  std::string_view head = take_until(rest, '=');
  if (!rest.empty()) {
    const auto* end = rest.data() + rest.size();
    const auto parsed = std::from_chars(rest.data(), end, effect.size);
    if (parsed.ec != std::errc{} || parsed.ptr != end || effect.size < 0.0) {
      error = "effect '" + std::string(spec) + "': size '" + std::string(rest) +
              "' is not a number >= 0";
      return std::nullopt;
    }
  }
  const std::string_view name = take_until(head, ':');
  const auto& info = catalogue();
  const auto* found =
      std::find_if(info.begin(), info.end(), [&](const EffectInfo& e) { return e.name == name; });
  if (found == info.end()) {
    error = "effect '" + std::string(spec) + "': unknown effect name '" + std::string(name) + "'";
    return std::nullopt;
  }
  effect.kind = found->kind;
  if (effect.kind == EffectKind::kCovariate) {
    effect.covariate = std::string(take_until(head, ':'));
    if (effect.covariate.empty()) {
      error =
          "effect '" + std::string(spec) + "': covariate needs a key, e.g. covariate:post_mortem_h";
      return std::nullopt;
    }
  }
  effect.form = std::string(head);
  if (!effect.form.empty() &&
      std::find(found->forms.begin(), found->forms.end(), effect.form) == found->forms.end()) {
    error =
        "effect '" + std::string(spec) + "': unknown form '" + effect.form + "' of " + found->name;
    return std::nullopt;
  }
  return effect;
}

ActiveEffects::ActiveEffects(const std::vector<HiddenEffect>& effects) {
  for (const auto& effect : effects) {
    EffectSlot& slot = slots_[static_cast<int>(effect.kind)];
    slot.on = true;
    slot.size = effect.size;
    const auto forms = effect_forms(effect.kind);
    const auto at = std::find(forms.begin(), forms.end(), effect.form);
    slot.form = at == forms.end() ? 0 : static_cast<int>(at - forms.begin());
    if (effect.kind == EffectKind::kCovariate) covariate_key_ = effect.covariate;
  }
}

void ActiveEffects::new_run(RandomSource& rng) {
  // The same number of draws whatever is switched on, so the noise does not depend on it.
  for (auto& slot : slots_) {
    slot.phase_rad = rng.uniform(0.0, 6.283185307179586);
    slot.run_factor = rng.sign() * rng.uniform(0.5, 1.5);
    for (double& value : slot.run_values) value = rng.uniform(0.0, 1.0);
  }
  effect_rng_.reseed(static_cast<std::uint64_t>(rng.uniform(0.0, 9.0e15)));
}

}  // namespace rig::sim
