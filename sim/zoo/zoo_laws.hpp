#pragma once
// Force laws the effect zoo draws at random, none of them a model-lab term: smooth random
// functions of depth confined to one phase and direction, random laws in velocity, random
// covariate links, and an oscillation in the hold. Each is an ExtraForce (sim/physics).
#include <string>
#include <vector>

#include "rig/sim/extra_force.hpp"
#include "rig/sim/random_source.hpp"

namespace rig::zoo {

// Where a law acts: the phase of the cut and the direction of motion.
enum class Window { kPrecutInsert, kCutInsert, kRetraction, kAllInsert, kAll };
bool in_window(Window window, const sim::ForceContext& c);
std::string window_name(Window window);

// A smooth random function of depth: a sum of Gaussian bumps [N at amplitude 1].
struct BumpSum {
  std::vector<double> centre_mm, width_mm, weight;
  static BumpSum draw(sim::RandomSource& rng, double from_mm, double to_mm);
  double operator()(double depth_mm) const;
};

// A random monotone law in velocity, normalised to 0 at 2 mm/s: a positive combination of
// saturating, logarithmic and power pieces with random knees.
struct VelocityLaw {
  double knee_mm_s = 1.0, weight_saturating = 0.0, weight_log = 0.0, weight_power = 0.0,
         exponent = 0.5;
  static VelocityLaw draw(sim::RandomSource& rng);
  double operator()(double v_mm_s) const;
};

// Extra force = amplitude * bumps(depth) inside the window (depth from the puncture when
// the window is after it).
class DepthBumpsLaw : public sim::ExtraForce {
 public:
  DepthBumpsLaw(BumpSum bumps, Window window, double amplitude_N)
      : bumps_(std::move(bumps)), window_(window), amplitude_N_(amplitude_N) {}
  double force_N(const sim::ForceContext& c) const override;

 private:
  BumpSum bumps_;
  Window window_;
  double amplitude_N_;
};

// The most a zoo law weakens the tissue: its force times (1 - 0.9), never turned over.
inline constexpr double kMostWeakening = -0.9;

// Tissue force scaled by (1 + amplitude * law(v)) inside the window, at least by 0.1.
class VelocityScaledLaw : public sim::ExtraForce {
 public:
  VelocityScaledLaw(VelocityLaw law, Window window, double amplitude)
      : law_(law), window_(window), amplitude_(amplitude) {}
  double force_N(const sim::ForceContext& c) const override;

 private:
  VelocityLaw law_;
  Window window_;
  double amplitude_;
};

// Tissue force scaled by a fixed per-run factor (the covariate link evaluated for the run).
class RunFactorLaw : public sim::ExtraForce {
 public:
  RunFactorLaw(double factor_minus_one, Window window)
      : excess_(factor_minus_one), window_(window) {}
  double force_N(const sim::ForceContext& c) const override;

 private:
  double excess_;
  Window window_;
};

// A damped oscillation in every hold: amplitude * exp(-t/decay) sin(2 pi t / period).
class HoldRingingLaw : public sim::ExtraForce {
 public:
  HoldRingingLaw(double amplitude_N, double period_s, double decay_s)
      : amplitude_N_(amplitude_N), period_s_(period_s), decay_s_(decay_s) {}
  double force_N(const sim::ForceContext& c) const override;

 private:
  double amplitude_N_, period_s_, decay_s_;
};

}  // namespace rig::zoo
