#pragma once
// Transducers and converter of the simulated DAQ: load cell, potentiometer and IOP
// transducer to volts, with offsets, noise, 16-bit quantisation and the instrument
// effects (drift, mains pick-up, lead-screw ripple).
#include "rig/drivers/analog_input.hpp"
#include "rig/sim/active_effects.hpp"
#include "rig/sim/physics_params.hpp"
#include "rig/sim/random_source.hpp"

namespace rig::sim {

struct TrueSignals {
  double force_N = 0.0;      // axial force on the keratome
  double carriage_mm = 0.0;  // carriage position from home
  double iop_mmHg = 0.0;
  double time_s = 0.0;      // simulation time
  double run_time_s = 0.0;  // time since the eye was mounted
  double carriage_velocity_mm_s = 0.0;
};

class SensorChain {
 public:
  SensorChain(const SensorParams& params, const ActiveEffects& effects, double screw_pitch_mm)
      : p_(params), effects_(&effects), screw_pitch_mm_(screw_pitch_mm) {}

  drivers::AnalogFrame convert(const TrueSignals& truth, RandomSource& rng) const;
  // Moves the slow instrument state (the random-walk drift) on by dt [s].
  void advance(double dt_s);
  void new_eye() { random_walk_N_ = 0.0; }
  // Force the load cell reports before offset and noise (effects included) [N].
  double instrument_force_N(const TrueSignals& truth) const;

 private:
  double quantise(double volts) const;
  SensorParams p_;
  const ActiveEffects* effects_;
  double screw_pitch_mm_;
  double random_walk_N_ = 0.0;
};

}  // namespace rig::sim
