#pragma once
// What makes one eye differ from the population model: the scale of its tissue force before
// the puncture (stiffness of the intact cornea) and after it (cutting), and a shift of the
// puncture depth (random effects, one set per run), and how widely they spread over the
// eyes of a data set.
#include <vector>

namespace rig::model {

struct EyeParams {
  double precut_scale =
      0.0;  // relative: before the puncture the tissue force is (1 + s) x the model's
  double cut_scale = 0.0;  // relative: from the puncture on
  double x_pi_mm = 0.0;    // this eye punctures x_pi_mm deeper than the model says [mm]
};

// Population standard deviations (tau) of the eye parameters, estimated from the runs.
struct EyeSpread {
  double precut_scale = 0.0;
  double cut_scale = 0.0;
  double x_pi_mm = 0.0;
  bool any() const { return precut_scale > 0.0 || cut_scale > 0.0 || x_pi_mm > 0.0; }
};

// How many fitted parameters each eye parameter's population value depends on through
// numbers fixed per run (the baseline's level; a law in the run's velocity, IOP or a
// covariate). Each takes one degree of freedom from the eyes' spread: over n eyes,
// sum(d_r^2) estimates (n - count) (tau^2 + v), not n (tau^2 + v) (eye_variation.hpp).
struct EyeDof {
  int precut_scale = 0;
  int cut_scale = 0;
  int x_pi_mm = 0;
  EyeDof& operator+=(const EyeDof& o) {
    precut_scale += o.precut_scale;
    cut_scale += o.cut_scale;
    x_pi_mm += o.x_pi_mm;
    return *this;
  }
};

// The tissue force before an eye's scales, split by where each scale acts (the derivatives
// of the prediction by precut_scale and cut_scale) [N].
struct EyeColumns {
  std::vector<double> precut;
  std::vector<double> cut;
};

}  // namespace rig::model
