#pragma once
// The model lab's self-contained HTML report (compare, diagnose and fit): measured vs model,
// the signed residual against depth (insertion and retraction apart), against time in the
// hold, per-run small multiples, error by phase, depth band and covariate, residual spectra;
// for fit (and diagnose with a verdict) the model before and after, overlaid. uPlot and the
// page's lab plots (web/lab_plots.js) are inlined, so the file opens anywhere offline.
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "comparison.hpp"
#include "report/report_assets.hpp"

namespace rig::model {

struct ReportContent {
  std::string kind = "compare";        // compare, diagnose or fit (the title)
  const Comparison* before = nullptr;  // required: the model as given (or refitted)
  const Comparison* after = nullptr;   // optional: the model after the fit
  nlohmann::json lab;                  // the command's JSON (diagnosis or fit), shown as tables
};

const char* report_template();
std::string render_report(const std::vector<RunData>& runs, const ReportContent& content,
                          const ReportAssets& assets);

}  // namespace rig::model
