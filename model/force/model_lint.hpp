#pragma once
// `rig model lint`: what is wrong or surprising in a model file, with sizes.
#include <optional>
#include <string>
#include <vector>

#include "force_model.hpp"

namespace rig::model {

struct LintFinding {
  enum class Severity { kError, kWarning, kInfo };
  Severity severity = Severity::kInfo;
  std::string what;       // the finding, in words
  double x_mm = 0.0;      // where (discontinuities)
  double iop_mmHg = 0.0;  // for which IOP
  double size_N = 0.0;    // jump (right - left) at a discontinuity
  double lowest_N = 0.0;  // the most negative force of a piece that goes below zero
};

std::vector<LintFinding> lint_model(const ForceModel& model);
std::string to_string(LintFinding::Severity severity);

// Eq. 1 as printed read without the stray `k` (names minus k, values kept in order: h, m
// and n then all have values), if the printed list has exactly one name too many and `k`
// among them; the caller compares both readings.
std::optional<ForceModel> reading_without_k(const ForceModel& printed);
// The warning every path that evaluates a printed-form file gives (compare, rigd's overlay):
// it runs as printed, with the defects lint lists.
std::string printed_form_warning(const ForceModel& model);
// Why a printed-form file cannot be used for `what` (diagnose, fit, refit).
std::string printed_form_refusal(const ForceModel& model, const std::string& what);

}  // namespace rig::model
