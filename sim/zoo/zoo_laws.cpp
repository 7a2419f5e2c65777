#include "zoo_laws.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace rig::zoo {

bool in_window(Window window, const sim::ForceContext& c) {
  if (c.tip_mm <= 0.0) return false;
  const bool inserting =
      c.velocity_mm_s > 0.05 || (c.hold_s > 0.0 && c.tip_mm >= c.front_mm - 0.05);
  const bool retracting = c.velocity_mm_s < -0.05 && c.tip_mm < c.front_mm - 0.01;
  switch (window) {
    case Window::kPrecutInsert:
      return !c.punctured && inserting;
    case Window::kCutInsert:
      return c.punctured && inserting;
    case Window::kRetraction:
      return retracting;
    case Window::kAllInsert:
      return inserting;
    case Window::kAll:
      return true;
  }
  return false;
}

std::string window_name(Window window) {
  switch (window) {
    case Window::kPrecutInsert:
      return "before the puncture, inserting";
    case Window::kCutInsert:
      return "after the puncture, inserting";
    case Window::kRetraction:
      return "retracting";
    case Window::kAllInsert:
      return "inserting";
    case Window::kAll:
      return "everywhere";
  }
  return "?";
}

BumpSum BumpSum::draw(sim::RandomSource& rng, double from_mm, double to_mm) {
  BumpSum sum;
  const int count = 2 + static_cast<int>(rng.uniform(0.0, 3.0));  // 2-4 bumps
  for (int k = 0; k < count; ++k) {
    sum.centre_mm.push_back(rng.uniform(from_mm, to_mm));
    sum.width_mm.push_back(rng.uniform(0.25, 1.2));
    sum.weight.push_back(rng.sign() * rng.uniform(0.4, 1.0));
  }
  return sum;
}

double BumpSum::operator()(double depth_mm) const {
  double value = 0.0;
  for (std::size_t k = 0; k < centre_mm.size(); ++k) {
    const double z = (depth_mm - centre_mm[k]) / width_mm[k];
    value += weight[k] * std::exp(-0.5 * z * z);
  }
  return value;
}

VelocityLaw VelocityLaw::draw(sim::RandomSource& rng) {
  VelocityLaw law;
  law.knee_mm_s = std::exp(rng.uniform(std::log(0.3), std::log(3.0)));
  law.weight_saturating = rng.uniform(0.0, 1.0);
  law.weight_log = rng.uniform(0.0, 1.0);
  law.weight_power = rng.uniform(0.0, 1.0);
  law.exponent = rng.uniform(0.3, 1.2);
  return law;
}

double VelocityLaw::operator()(double v) const {
  auto raw = [&](double u) {
    u = std::max(u, 0.05);
    return weight_saturating * std::tanh(u / knee_mm_s) + weight_log * std::log1p(u / knee_mm_s) +
           weight_power * std::pow(u / 4.0, exponent);
  };
  return raw(v) - raw(2.0);
}

double DepthBumpsLaw::force_N(const sim::ForceContext& c) const {
  if (!in_window(window_, c)) return 0.0;
  const bool from_puncture = window_ == Window::kCutInsert;
  return amplitude_N_ * bumps_(from_puncture ? c.tip_mm - c.punctured_at_mm : c.tip_mm);
}

double VelocityScaledLaw::force_N(const sim::ForceContext& c) const {
  if (!in_window(window_, c)) return 0.0;
  // A viscous-like law: it vanishes at rest (law(2 mm/s) = 0 stands in for 'no change').
  // A law can weaken the tissue to a tenth, never turn its force over: a tissue that pulls
  // the blade in is no rate law (large draws did, down to -0.2 N on the start-up after a stop).
  const double change =
      amplitude_ * law_(std::abs(c.velocity_mm_s) > 0.05 ? std::abs(c.velocity_mm_s) : 2.0);
  return std::max(kMostWeakening, change) * c.tissue_force_N;
}

double RunFactorLaw::force_N(const sim::ForceContext& c) const {
  return in_window(window_, c) ? excess_ * c.tissue_force_N : 0.0;
}

double HoldRingingLaw::force_N(const sim::ForceContext& c) const {
  if (c.hold_s <= 0.0 || c.tip_mm <= 0.0) return 0.0;
  return amplitude_N_ * std::exp(-c.hold_s / decay_s_) *
         std::sin(2.0 * std::numbers::pi * c.hold_s / period_s_);
}

}  // namespace rig::zoo
