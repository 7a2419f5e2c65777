#include "html_report.hpp"

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "lab_json.hpp"

namespace rig::model {
namespace {

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

void replace(std::string& text, const std::string& marker, const std::string& with) {
  const auto at = text.find(marker);
  if (at != std::string::npos) text.replace(at, marker.size(), with);
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
    for (std::size_t g = 0; g < grid.size(); ++g) {
      const std::size_t end = c.runs[r].segmentation.insertion_end;
      while (i < end && runs[r].x_mm[i] < grid[g]) ++i;
      measured[g] = runs[r].force_N[i];
      model[g] = c.runs[r].prediction[i];
    }
    out["runs"].push_back({{"label", c.runs[r].label}, {"measured", measured}, {"model", model}});
  }
  return out;
}

nlohmann::json residual(const Comparison& c, const std::vector<RunData>& runs) {
  nlohmann::json out = {{"label", c.runs.front().label}, {"t", nlohmann::json::array()}, {"residual", nlohmann::json::array()},
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
      out["phases"].push_back({{"phase", phase_name(seg.phase[begin])}, {"t0", run.t_s[begin]}, {"t1", run.t_s[i - 1]}});
      begin = i;
    }
  }
  return out;
}

}  // namespace

std::pair<std::string, std::string> find_uplot(const std::string& executable_dir) {
  std::vector<std::filesystem::path> places;
  if (const char* root = std::getenv("RIG_WEB_ROOT")) places.emplace_back(std::filesystem::path(root) / "vendor");
  places.emplace_back(std::filesystem::path(executable_dir) / ".." / "web" / "vendor");
  places.emplace_back(std::filesystem::path(executable_dir) / ".." / "share" / "rigd" / "web" / "vendor");
  places.emplace_back("/usr/share/rigd/web/vendor");
  std::string looked;
  for (const auto& dir : places) {
    if (std::filesystem::exists(dir / "uPlot.iife.min.js")) {
      return {read_file(dir / "uPlot.iife.min.js"), read_file(dir / "uPlot.min.css")};
    }
    looked += " " + dir.string();
  }
  throw std::runtime_error("report: uPlot not found (looked in" + looked + "); set RIG_WEB_ROOT to the page's directory");
}

std::string render_report(const Comparison& comparison, const std::vector<RunData>& runs,
                          const std::pair<std::string, std::string>& uplot) {
  if (comparison.runs.empty()) throw std::invalid_argument("report: no runs");
  nlohmann::json data = {{"comparison", to_json(comparison)}, {"curves", curves(comparison, runs)},
                         {"residual", residual(comparison, runs)}};
  // Spectra in full for the plots (the comparison's JSON keeps only the peaks).
  data["spectrum_time"] = {{"frequency", comparison.time_frequency_Hz}, {"amplitude", comparison.time_amplitude_N}};
  data["spectrum_x"] = {{"frequency", comparison.x_frequency_per_mm}, {"amplitude", comparison.x_amplitude_N}};
  std::string html = report_template();
  std::string json = data.dump();
  for (std::size_t at = json.find("</"); at != std::string::npos; at = json.find("</", at + 2)) json.replace(at, 2, "<\\/");
  replace(html, "/*UPLOT_CSS*/", uplot.second);
  replace(html, "/*UPLOT_JS*/", uplot.first);
  replace(html, "/*DATA*/", json);
  return html;
}

}  // namespace rig::model
