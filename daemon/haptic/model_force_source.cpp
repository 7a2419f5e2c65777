#include "model_force_source.hpp"

#include <algorithm>
#include <cmath>

namespace rig::haptic {

ModelForceSource::ModelForceSource(const model::ForceModel& model, double iop_mmHg)
    : model_(model), iop_mmHg_(iop_mmHg), x_pi_mm_(model.puncture_depth_mm(iop_mmHg)) {
  for (const auto& e : model.effects) {
    if (e.name == "shaft_friction")
      friction_mu_ = e.params.at("mu"), friction_kappa_ = e.params.at("kappa");
    if (e.name == "rate_dependence") rate_b1_ = e.params.at("b1"), rate_b2_ = e.params.at("b2");
  }
}

double ModelForceSource::force_N(double depth_mm, double front_mm,
                                 double velocity_mm_s) const noexcept {
  double force = model_.baseline(depth_mm, front_mm, iop_mmHg_);
  if (rate_b1_ != 0.0 || rate_b2_ != 0.0) {
    const double u =
        std::log(std::max(std::abs(velocity_mm_s), 0.05) / model_.reference_velocity_mm_s);
    force *= std::exp(rate_b1_ * u + rate_b2_ * u * u);
  }
  const double inserted = std::max(0.0, std::min(depth_mm, front_mm) - x_pi_mm_);
  if (friction_mu_ != 0.0 && inserted > 0.0 && front_mm > x_pi_mm_) {
    const double length = friction_kappa_ == 0.0
                              ? inserted
                              : -std::expm1(-friction_kappa_ * inserted) / friction_kappa_;
    force += friction_mu_ * length * std::tanh(velocity_mm_s / 0.05);
  }
  return force;
}

}  // namespace rig::haptic
