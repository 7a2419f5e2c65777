#include "report_series.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rig::model {
namespace {

// Mean signed residual per depth bin, for one direction of travel.
struct DepthBins {
  DepthBins(std::size_t count, double width) : sum(count, 0.0), n(count, 0), width_mm(width) {}
  void add(double x_mm, double residual_N) {
    if (x_mm < 0.0) return;
    const auto bin = std::min(sum.size() - 1, static_cast<std::size_t>(x_mm / width_mm));
    sum[bin] += residual_N;
    ++n[bin];
  }
  nlohmann::json means() const {
    nlohmann::json out = nlohmann::json::array();
    for (std::size_t b = 0; b < sum.size(); ++b) {
      if (n[b] == 0) {
        out.push_back(nullptr);
      } else {
        out.push_back(sum[b] / static_cast<double>(n[b]));
      }
    }
    return out;
  }
  std::vector<double> sum;
  std::vector<std::size_t> n;
  double width_mm;
};

bool inserting(const Segmentation& seg, std::size_t i) {
  return i <= seg.insertion_end && seg.phase[i] != Phase::kApproach;
}
bool retracting(const Segmentation& seg, std::size_t i) {
  return seg.phase[i] == Phase::kRetraction;
}

double residual(const RunData& run, const RunComparison& c, std::size_t i) {
  return run.force_N[i] - c.prediction[i];
}

nlohmann::json depth_series(const std::vector<RunData>& runs, const Comparison& before,
                            const Comparison* after, const SeriesLimits& limits) {
  double deepest = 0.0;
  for (const auto& r : before.runs) deepest = std::max(deepest, r.segmentation.max_depth_mm);
  const double width = std::max(
      0.05,
      std::ceil(std::max(deepest, 0.05) / static_cast<double>(limits.depth_bins) / 0.05) * 0.05);
  const auto count = static_cast<std::size_t>(std::max(1.0, std::ceil(deepest / width)));
  DepthBins in(count, width), out(count, width), in_after(count, width), out_after(count, width);
  for (std::size_t r = 0; r < runs.size(); ++r) {
    const Segmentation& seg = before.runs[r].segmentation;
    for (std::size_t i = 0; i < runs[r].size(); ++i) {
      const bool ins = inserting(seg, i), ret = retracting(seg, i);
      if (!ins && !ret) continue;
      (ins ? in : out).add(runs[r].x_mm[i], residual(runs[r], before.runs[r], i));
      if (after != nullptr)
        (ins ? in_after : out_after).add(runs[r].x_mm[i], residual(runs[r], after->runs[r], i));
    }
  }
  nlohmann::json x = nlohmann::json::array();
  for (std::size_t b = 0; b < count; ++b) x.push_back((static_cast<double>(b) + 0.5) * width);
  nlohmann::json j = {
      {"x_mm", x}, {"bin_mm", width}, {"insertion_N", in.means()}, {"retraction_N", out.means()}};
  if (after != nullptr) {
    j["after_insertion_N"] = in_after.means();
    j["after_retraction_N"] = out_after.means();
  }
  return j;
}

std::size_t stride(std::size_t samples, std::size_t points) {
  return std::max<std::size_t>(1, (samples + points - 1) / std::max<std::size_t>(points, 1));
}

nlohmann::json hold_series(const std::vector<RunData>& runs, const Comparison& before,
                           const Comparison* after, const SeriesLimits& limits) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t r = 0; r < runs.size() && out.size() < limits.runs_shown; ++r) {
    const Segmentation& seg = before.runs[r].segmentation;
    if (seg.hold_end <= seg.hold_begin) continue;
    nlohmann::json trace = {{"label", before.runs[r].label},
                            {"t_s", nlohmann::json::array()},
                            {"residual_N", nlohmann::json::array()}};
    if (after != nullptr) trace["after_residual_N"] = nlohmann::json::array();
    const double t0 = runs[r].t_s[seg.hold_begin];
    for (std::size_t i = seg.hold_begin; i < seg.hold_end;
         i += stride(seg.hold_end - seg.hold_begin, limits.points_per_run)) {
      trace["t_s"].push_back(runs[r].t_s[i] - t0);
      trace["residual_N"].push_back(residual(runs[r], before.runs[r], i));
      if (after != nullptr)
        trace["after_residual_N"].push_back(residual(runs[r], after->runs[r], i));
    }
    out.push_back(std::move(trace));
  }
  return out;
}

nlohmann::json run_panels(const std::vector<RunData>& runs, const Comparison& before,
                          const Comparison* after, const SeriesLimits& limits) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t r = 0; r < runs.size() && r < limits.runs_shown; ++r) {
    const RunData& run = runs[r];
    nlohmann::json panel = {{"label", before.runs[r].label},
                            {"rmse_N", before.runs[r].overall.rmse_N}};
    std::vector<double> t, x, measured, model, fitted;
    for (std::size_t i = 0; i < run.size(); i += stride(run.size(), limits.points_per_run)) {
      t.push_back(run.t_s[i]);
      x.push_back(run.x_mm[i]);
      measured.push_back(run.force_N[i]);
      model.push_back(before.runs[r].prediction[i]);
      if (after != nullptr) fitted.push_back(after->runs[r].prediction[i]);
    }
    panel["t_s"] = t;
    panel["x_mm"] = x;
    panel["measured_N"] = measured;
    panel["model_N"] = model;
    if (after != nullptr) {
      panel["after_N"] = fitted;
      panel["after_rmse_N"] = after->runs[r].overall.rmse_N;
    }
    out.push_back(std::move(panel));
  }
  return out;
}

}  // namespace

nlohmann::json report_series(const std::vector<RunData>& runs, const Comparison& before,
                             const Comparison* after, const SeriesLimits& limits) {
  if (before.runs.size() != runs.size() ||
      (after != nullptr && after->runs.size() != runs.size())) {
    throw std::invalid_argument("report: the comparisons do not cover the same runs");
  }
  if (runs.empty()) throw std::invalid_argument("report: no runs");
  nlohmann::json j = {{"before", before.model_name},
                      {"depth", depth_series(runs, before, after, limits)},
                      {"hold", hold_series(runs, before, after, limits)},
                      {"runs", run_panels(runs, before, after, limits)}};
  if (after != nullptr) j["after"] = after->model_name;
  return j;
}

}  // namespace rig::model
