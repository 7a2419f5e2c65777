#pragma once
// Physical and instrument effects the simulated rig can hide in its data. Names match the
// model lab's effect catalogue; each has several forms so that a test does not only hide
// an effect in exactly the form of the term that finds it.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rig::sim {

enum class EffectKind {
  kRateDependence,     // force grows with keratome velocity
  kIopStiffness,       // pre-cut stiffness grows with IOP
  kShaftFriction,      // friction along the inserted blade, opposes motion
  kRigCompliance,      // tip lags the carriage by F/k
  kSensorDrift,        // load-cell offset wanders during a run
  kSpatialRipple,      // periodic in carriage position (lead-screw pitch)
  kMainsInterference,  // 50/60 Hz on the force channel
  kStickSlip,          // periodic tearing during the cut
  kStressRelaxation,   // force decays during a hold
  kCovariate,          // a run covariate (metadata) scales the cutting force
};

struct HiddenEffect {
  EffectKind kind = EffectKind::kRateDependence;
  std::string form;       // "" = the effect's default form
  double size = 1.0;      // multiple of the nominal magnitude
  std::string covariate;  // kCovariate: metadata key, e.g. post_mortem_h
};

// Parses "name[:form][=size]" or "covariate:KEY[:form][=size]".
// Returns std::nullopt and sets `error` (naming the bad part) on failure.
std::optional<HiddenEffect> parse_hidden_effect(std::string_view spec, std::string& error);
std::string effect_name(EffectKind kind);
std::vector<std::string> effect_forms(EffectKind kind);

}  // namespace rig::sim
