#pragma once
// The page assets a self-contained report inlines (uPlot's JS and CSS, and the page's own
// lab plots, web/lab_plots.js, so the report and the page's Model lab tab draw the same
// plots). Searched, in order: $RIG_WEB_ROOT; the build tree (<bin>/../web-root, where the
// target web_assets copies the page); the install prefix (<bin>/../share/rigd/web, the .deb
// puts rig in /usr/bin and the page in /usr/share/rigd/web); /usr/share/rigd/web.
#include <string>
#include <vector>

namespace rig::model {

struct ReportAssets {
  std::string uplot_js, uplot_css, lab_plots_js;
  std::string web_root;  // where they were found
};

std::vector<std::string> report_asset_places(const std::string& executable_dir);
// Throws std::runtime_error naming every place it looked.
ReportAssets find_report_assets(const std::string& executable_dir);

}  // namespace rig::model
