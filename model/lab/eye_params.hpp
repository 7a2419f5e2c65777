#pragma once
// What makes one eye differ from the population model: a tissue-force scale and a shift of
// the puncture depth (random effects, one pair per run), and how widely they spread over
// the eyes of a data set.
namespace rig::model {

struct EyeParams {
  double scale = 0.0;    // relative: the tissue force of this eye is (1 + scale) x the model's
  double x_pi_mm = 0.0;  // this eye punctures x_pi_mm deeper than the model says [mm]
};

// Population standard deviations (tau) of the eye parameters, estimated from the runs.
struct EyeSpread {
  double scale = 0.0;
  double x_pi_mm = 0.0;
  bool any() const { return scale > 0.0 || x_pi_mm > 0.0; }
};

}  // namespace rig::model
