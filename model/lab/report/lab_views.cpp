#include "report/lab_views.hpp"

#include <nlohmann/json.hpp>

#include "model_lint.hpp"
#include "report/report_series.hpp"

namespace rig::model {

LabViews compare_views(const ForceModel& model, const std::vector<RunData>& runs, bool refit) {
  return {compare(model, runs, refit), std::nullopt};
}

LabViews diagnose_views(const ForceModel& model, const std::vector<RunData>& runs) {
  require_fittable(model, "diagnose");
  return {compare(model, runs, true), std::nullopt};
}

LabViews fit_views(const ForceModel& model, const ForceModel& fitted,
                   const std::vector<RunData>& runs) {
  require_fittable(model, "fit");
  return {compare(model, runs, true), compare(fitted, runs, false)};
}

nlohmann::json views_series(const std::vector<RunData>& runs, const LabViews& views) {
  return report_series(runs, views.before, views.after ? &*views.after : nullptr);
}

void require_fittable(const ForceModel& model, const std::string& what) {
  if (model.form == ModelForm::kPrinted) throw ModelFileError(printed_form_refusal(model, what));
}

}  // namespace rig::model
