#pragma once
// The explainer's proposal as JSON (`rig model explain --format json`; keys documented in
// docs/model-lab.md).
#include <nlohmann/json_fwd.hpp>

#include "explanation.hpp"

namespace rig::model::explainer {

nlohmann::json to_json(const Explanation& e);

}  // namespace rig::model::explainer
