#pragma once
// `rig model lint`: what is wrong or surprising in a model file, with sizes.
#include <string>
#include <vector>

#include "force_model.hpp"

namespace rig::model {

struct LintFinding {
  enum class Severity { kError, kWarning, kInfo };
  Severity severity = Severity::kInfo;
  std::string what;            // the finding, in words
  double x_mm = 0.0;           // where (discontinuities)
  double iop_mmHg = 0.0;       // for which IOP
  double size_N = 0.0;         // jump (right - left) at a discontinuity
};

std::vector<LintFinding> lint_model(const ForceModel& model);
std::string to_string(LintFinding::Severity severity);

}  // namespace rig::model
