#include "explanation_json.hpp"

#include <nlohmann/json.hpp>

namespace rig::model::explainer {
namespace {

nlohmann::json term_json(const UserTerm& t) {
  return {{"name", t.name}, {"expression", t.expression}, {"phase", t.phase}, {"params", t.params}};
}

}  // namespace

nlohmann::json to_json(const Explanation& e) {
  nlohmann::json features = nlohmann::json::array();
  for (const ExplainedFeature& f : e.features) {
    features.push_back({{"parameter", f.parameter},
                        {"feature", f.expression},
                        {"gate", f.gate},
                        {"coefficient", f.coefficient},
                        {"contribution_N", f.contribution_N}});
  }
  nlohmann::json path = nlohmann::json::array();
  for (const auto& [size, rmse] : e.path) path.push_back({{"features", size}, {"cv_rmse_N", rmse}});
  nlohmann::json out = {{"proposed", e.proposed},
                        {"summary", e.summary},
                        {"baseline",
                         {{"cv_rmse_N", e.baseline_cv_rmse_N},
                          {"noise_floor_N", e.noise_floor_N},
                          {"effects", e.base_effects}}},
                        {"library_size", e.library_size},
                        {"path", path},
                        {"warnings", e.warnings}};
  if (e.features.empty()) return out;
  out.update({{"term", term_json(e.term)},
              {"features", features},
              {"where", e.where},
              {"predicted",
               {{"cv_rmse_N", e.predicted_cv_rmse_N},
                {"gain_pct", e.predicted_gain_pct},
                {"runs_improved", e.runs_improved}}}});
  if (e.validated) {
    out["after"] = {{"cv_rmse_N", e.after_cv_rmse_N},
                    {"gain_pct", e.after_gain_pct},
                    {"runs_improved", e.after_runs_improved},
                    {"term", term_json(e.fitted)}};
  }
  return out;
}

}  // namespace rig::model::explainer
