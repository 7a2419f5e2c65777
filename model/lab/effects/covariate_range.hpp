#pragma once
#include <limits>

namespace rig::model::effects {

// A covariate's centre and scale across the runs a term is fitted on, and the values seen
// there: the term never extrapolates beyond them (a held-out run outside the range is
// predicted as at its edge; a step or a bend in the covariate's effect would otherwise be
// extended as a slope far past the data, the way 9 runs of a cross-validation see it).
struct CovariateRange {
  double mean = 0.0;
  double spread = 1.0;
  double low = -std::numeric_limits<double>::infinity();
  double high = std::numeric_limits<double>::infinity();
};

}  // namespace rig::model::effects
