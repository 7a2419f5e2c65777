#include "html_report.hpp"

#include <algorithm>
#include <stdexcept>

#include "lab_json.hpp"
#include "report/report_series.hpp"

namespace rig::model {
namespace {

void replace(std::string& text, const std::string& marker, const std::string& with) {
  const auto at = text.find(marker);
  if (at == std::string::npos) throw std::logic_error("report template lacks " + marker);
  text.replace(at, marker.size(), with);
}

// Inlined scripts and data must not close their <script> element early.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

nlohmann::json curves(const Comparison& c, const std::vector<RunData>& runs) {
  nlohmann::json out = {{"x", nlohmann::json::array()}, {"runs", nlohmann::json::array()}};
  std::vector<double> grid;  // common x grid over the insertion, 0.02 mm
  double deepest = 0.0;
  for (const auto& r : c.runs) deepest = std::max(deepest, r.segmentation.max_depth_mm);
  for (double x = 0.0; x <= deepest; x += 0.02) grid.push_back(x);
  out["x"] = grid;
  for (std::size_t r = 0; r < runs.size() && r < 6; ++r) {
    std::vector<double> measured(grid.size()), model(grid.size());
    std::size_t i = 0;
    const std::size_t end = c.runs[r].segmentation.insertion_end;
    for (std::size_t g = 0; g < grid.size(); ++g) {
      while (i < end && runs[r].x_mm[i] < grid[g]) ++i;
      measured[g] = runs[r].force_N[i];
      model[g] = c.runs[r].prediction[i];
    }
    out["runs"].push_back({{"label", c.runs[r].label}, {"measured", measured}, {"model", model}});
  }
  return out;
}

nlohmann::json residual_in_time(const Comparison& c, const std::vector<RunData>& runs) {
  nlohmann::json out = {{"label", c.runs.front().label},
                        {"t", nlohmann::json::array()},
                        {"residual", nlohmann::json::array()},
                        {"phases", nlohmann::json::array()}};
  const RunData& run = runs.front();
  const auto& seg = c.runs.front().segmentation;
  const std::size_t step = std::max<std::size_t>(1, run.size() / 4000);
  for (std::size_t i = 0; i < run.size(); i += step) {
    out["t"].push_back(run.t_s[i]);
    out["residual"].push_back(run.force_N[i] - c.runs.front().prediction[i]);
  }
  std::size_t begin = 0;
  for (std::size_t i = 1; i <= run.size(); ++i) {
    if (i == run.size() || seg.phase[i] != seg.phase[begin]) {
      out["phases"].push_back({{"phase", phase_name(seg.phase[begin])},
                               {"t0", run.t_s[begin]},
                               {"t1", run.t_s[i - 1]}});
      begin = i;
    }
  }
  return out;
}

}  // namespace

std::string render_report(const std::vector<RunData>& runs, const ReportContent& content,
                          const ReportAssets& assets) {
  if (content.before == nullptr || content.before->runs.empty() ||
      runs.size() != content.before->runs.size()) {
    throw std::invalid_argument("report: no runs");
  }
  const Comparison& c = *content.before;
  nlohmann::json data = {{"kind", content.kind},
                         {"comparison", to_json(c)},
                         {"curves", curves(c, runs)},
                         {"residual", residual_in_time(c, runs)},
                         {"series", report_series(runs, c, content.after)},
                         {"lab", content.lab}};
  if (content.after != nullptr) data["after"] = to_json(*content.after);
  // Spectra in full for the plots (the comparison's JSON keeps only the peaks).
  data["spectrum_time"] = {{"frequency", c.time_frequency_Hz}, {"amplitude", c.time_amplitude_N}};
  data["spectrum_x"] = {{"frequency", c.x_frequency_per_mm}, {"amplitude", c.x_amplitude_N}};
  std::string html = report_template();
  replace(html, "/*UPLOT_CSS*/", assets.uplot_css);
  replace(html, "/*UPLOT_JS*/", script_safe(assets.uplot_js));
  replace(html, "/*LAB_PLOTS_JS*/", script_safe(assets.lab_plots_js));
  replace(html, "/*DATA*/", script_safe(data.dump()));
  return html;
}

}  // namespace rig::model
