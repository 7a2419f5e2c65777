#pragma once
// The model lab's self-contained HTML report: measured vs model, residual with phases
// shaded, error by phase and depth band, error against covariates, residual spectra.
// uPlot (from the page's vendor directory) is inlined, so the file opens anywhere offline.
#include <string>
#include <vector>

#include "comparison.hpp"

namespace rig::model {

const char* report_template();
// uPlot's JS and CSS: searched in $RIG_WEB_ROOT/vendor, next to the executable's web
// directory, then /usr/share/rigd/web/vendor; throws naming every place it looked.
std::pair<std::string, std::string> find_uplot(const std::string& executable_dir);
std::string render_report(const Comparison& comparison, const std::vector<RunData>& runs,
                          const std::pair<std::string, std::string>& uplot);

}  // namespace rig::model
