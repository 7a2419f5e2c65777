#pragma once
#include <limits>

namespace rig::model::effects {

// A covariate's centre and scale across the runs a term is fitted on, and the values seen
// there. The term extrapolates no further than `reach` past them: a held-out run farther out
// is predicted as at low - reach or high + reach. Without a limit a step or a bend in the
// covariate's effect would be extended as a slope far past the data, the way 9 runs of a
// cross-validation see it (draw 70034: 25 C beside runs of 19.8-23.0 C, predicted 5x off).
// Held exactly to the edge, a law that is steepest at the edge loses its end: a blade's
// ninth use held to its eighth is predicted with the eighth's wear, and wear that bends
// upwards (300026) kept a third of its excess in the held-out error. So for a count (every
// run's value a whole number: blade uses, run order), whose next run is one step on, the
// reach is the runs' mean spacing, (high - low) / (runs - 1). A measured covariate
// (temperature, hours post mortem) keeps reach 0: a held-out run may lie several spacings
// out, and a step there is not predictable (70034 lost its verdict with a spacing's reach).
struct CovariateRange {
  double mean = 0.0;
  double spread = 1.0;
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
  double reach = 0.0;  // [covariate units]; 0: held to low..high (model files before 2026-12-07)
};

}  // namespace rig::model::effects
