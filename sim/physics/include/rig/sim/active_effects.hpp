#pragma once
// The hidden effects of one simulated eye, resolved to numbers: which form, how big, and
// the per-run random parts (phases, drift direction) that instrument effects have.
#include <array>
#include <string>
#include <vector>

#include "rig/sim/hidden_effect.hpp"
#include "rig/sim/random_source.hpp"

namespace rig::sim {

inline constexpr int kEffectKindCount = 10;

struct EffectSlot {
  bool on = false;
  int form = 0;                                 // index into effect_forms(kind)
  double size = 1.0;                            // multiple of the nominal magnitude
  double phase_rad = 0.0;                       // per-run phase (ripple, mains, stick-slip)
  double run_factor = 1.0;                      // per-run signed factor (drift direction and rate)
  double run_values[4] = {0.5, 0.5, 0.5, 0.5};  // per-run uniform draws (time constants, times)
};

class ActiveEffects {
 public:
  ActiveEffects() = default;
  explicit ActiveEffects(const std::vector<HiddenEffect>& effects);

  // Draws the per-run parts for a new eye.
  void new_run(RandomSource& rng);
  const EffectSlot& operator[](EffectKind kind) const { return slots_[static_cast<int>(kind)]; }
  bool on(EffectKind kind) const { return (*this)[kind].on; }

  const std::string& covariate_key() const { return covariate_key_; }
  double covariate_value() const { return covariate_value_; }
  void set_covariate_value(double value) { covariate_value_ = value; }
  // Random numbers the effects draw while a run goes on (tear spacing, random walk), apart
  // from the noise stream so that switching an effect on leaves the noise unchanged.
  RandomSource& effect_rng() const { return effect_rng_; }

 private:
  std::array<EffectSlot, kEffectKindCount> slots_{};
  std::string covariate_key_ = "post_mortem_h";
  double covariate_value_ = 2.0;
  mutable RandomSource effect_rng_{7};
};

}  // namespace rig::sim
