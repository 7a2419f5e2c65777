#pragma once
// The model lab's results as JSON: the formats `rig model ... --format json` prints and the
// API serves (keys documented in docs/model-lab.md; scripts depend on them).
#include <nlohmann/json_fwd.hpp>

#include <vector>

#include "comparison.hpp"
#include "diagnosis.hpp"
#include "model_fit.hpp"
#include "model_lint.hpp"

namespace rig::model {

nlohmann::json to_json(const Diagnosis& d);
nlohmann::json to_json(const FitReport& f);
nlohmann::json to_json(const Comparison& c);
nlohmann::json to_json(const SegmentMetrics& m);
nlohmann::json lint_json(const ForceModel& model, const std::vector<LintFinding>& findings);

}  // namespace rig::model
