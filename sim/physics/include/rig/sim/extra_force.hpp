#pragma once
// A force law from outside the simulator's own effect catalogue, added to the tissue force
// (the load cell and the motor both feel it). The effect zoo (sim/zoo) draws such laws at
// random; a law is made per run, so it can know the run's metadata (covariates).
namespace rig::sim {

struct ForceContext {
  double run_time_s = 0.0;      // since the eye was mounted
  double tip_mm = 0.0;          // depth of the blade tip from the surface
  double front_mm = 0.0;        // deepest depth reached so far
  double velocity_mm_s = 0.0;   // carriage velocity, + into the eye
  double tissue_force_N = 0.0;  // the tissue's force without this law
  double iop_mmHg = 15.0;
  double hold_s = 0.0;           // time at rest at the front (0 while moving)
  double punctured_at_mm = 0.0;  // where the blade entered (valid when punctured)
  bool punctured = false;
};

class ExtraForce {
 public:
  virtual ~ExtraForce() = default;
  virtual double force_N(const ForceContext& context) const = 0;
};

}  // namespace rig::sim
