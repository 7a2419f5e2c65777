#pragma once
// The force model from a model file (the paper's Eq. 1 as we read it, or a fit saved by the
// model lab) at one IOP. Of the lab's effects, those that change what a hand feels are
// rendered: shaft_friction and rate_dependence; instrument effects (drift, ripple, mains)
// are not tissue and are left out.
#include "force_model.hpp"
#include "force_source.hpp"

namespace rig::haptic {

class ModelForceSource final : public ForceSource {
 public:
  ModelForceSource(const model::ForceModel& model, double iop_mmHg);
  double force_N(double depth_mm, double front_mm, double velocity_mm_s) const noexcept override;
  const char* describe() const noexcept override { return "model"; }

 private:
  model::ForceModel model_;
  double iop_mmHg_;
  double friction_mu_ = 0.0, friction_kappa_ = 0.0;
  double rate_b1_ = 0.0, rate_b2_ = 0.0;
  double x_pi_mm_;
};

}  // namespace rig::haptic
