#pragma once
// What the report and the page's Model lab tab show for each lab command: the comparison
// "before" (compare: the model as given or refitted; diagnose: the refitted baseline the
// candidates compete against; fit: the refitted baseline) and, for fit, "after" (the fitted
// model with its effects). The CLI's --report and rigd's /api/lab/* both build them here.
#include <nlohmann/json_fwd.hpp>

#include <optional>
#include <string>
#include <vector>

#include "comparison.hpp"
#include "force_model.hpp"

namespace rig::model {

struct LabViews {
  Comparison before;
  std::optional<Comparison> after;
};

LabViews compare_views(const ForceModel& model, const std::vector<RunData>& runs, bool refit);
LabViews diagnose_views(const ForceModel& model, const std::vector<RunData>& runs);
LabViews fit_views(const ForceModel& model, const ForceModel& fitted,
                   const std::vector<RunData>& runs);
// The plotted series (report_series) of these views.
nlohmann::json views_series(const std::vector<RunData>& runs, const LabViews& views);
// Throws ModelFileError if `model` is a printed-form file: diagnose and fit need the
// continuous reading (compare runs the printed form as printed, with a warning).
void require_fittable(const ForceModel& model, const std::string& what);

}  // namespace rig::model
