#include "residual_structure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "correlation.hpp"

namespace rig::model {
namespace {

constexpr double kMoving_mm_s = 0.05;  // slower than this the blade counts as still

struct BinSum {
  double sse = 0.0, sum = 0.0;
  double n = 0.0;
};

using View = std::map<std::string, BinSum>;

std::string direction_of(const PreparedRun& run, std::size_t i) {
  const Phase phase = run.seg.phase[i];
  if (phase == Phase::kHold) return "holding";
  if (phase == Phase::kRetraction || run.velocity_mm_s[i] < -kMoving_mm_s) return "retracting";
  return run.velocity_mm_s[i] > kMoving_mm_s ? "inserting" : "holding";
}

std::string depth_band(double x_mm) {
  const int band = static_cast<int>(std::floor(x_mm));
  return std::to_string(band) + "-" + std::to_string(band + 1);
}

std::string hold_band(double hold_s) {
  if (hold_s < 0.5) return "0-0.5";
  return hold_s < 2.0 ? "0.5-2" : "2+";
}

void best_covariate(const std::vector<const PreparedRun*>& runs,
                    const std::vector<std::vector<double>>& residuals,
                    const std::vector<std::string>& keys, ResidualStructure& out) {
  if (runs.size() < 4) return;  // a correlation over fewer runs means nothing
  std::vector<double> mean_residual;
  for (const auto& r : residuals) {
    double sum = 0.0;
    for (const double e : r) sum += e;
    mean_residual.push_back(r.empty() ? 0.0 : sum / static_cast<double>(r.size()));
  }
  for (const std::string& key : keys) {
    std::vector<double> values;
    values.reserve(runs.size());
    for (const PreparedRun* run : runs) values.push_back(run->covariate(key, 0).value_or(0.0));
    const double c = correlation(values, mean_residual);
    if (std::abs(c) > std::abs(out.covariate_correlation))
      out.covariate = key, out.covariate_correlation = c;
  }
}

}  // namespace

ResidualStructure locate_excess(const std::vector<const PreparedRun*>& runs,
                                const std::vector<std::vector<double>>& residuals, double floor_N,
                                const std::vector<std::string>& covariates) {
  std::map<std::string, View> views;
  double total_excess = 0.0;
  const double floor_N2 = floor_N * floor_N;
  for (std::size_t r = 0; r < runs.size() && r < residuals.size(); ++r) {
    const PreparedRun& run = *runs[r];
    for (std::size_t k = 0; k < run.analysed.size() && k < residuals[r].size(); ++k) {
      const std::size_t i = run.analysed[k];
      const double e = residuals[r][k];
      total_excess += e * e - floor_N2;
      auto add = [&](const std::string& view, const std::string& bin) {
        BinSum& b = views[view][bin];
        b.sse += e * e, b.sum += e, b.n += 1.0;
      };
      add("phase", phase_name(run.seg.phase[i]));
      add("direction", direction_of(run, i));
      add("depth_mm", depth_band(run.data->x_mm[i]));
      if (run.seg.phase[i] == Phase::kHold) add("hold_s", hold_band(run.hold_s[i]));
    }
  }
  ResidualStructure out;
  for (const auto& [view, bins] : views) {
    ExcessBin best{view, "", -1e300, 0.0};
    for (const auto& [bin, sum] : bins) {
      const double excess = sum.sse - sum.n * floor_N2;
      if (excess > best.share) best = {view, bin, excess, sum.n > 0.0 ? sum.sum / sum.n : 0.0};
    }
    if (best.share <= 0.0 || total_excess <= 0.0) continue;
    best.share = std::min(1.0, best.share / total_excess);
    out.bins.push_back(best);
  }
  std::sort(out.bins.begin(), out.bins.end(),
            [](const ExcessBin& a, const ExcessBin& b) { return a.share > b.share; });
  best_covariate(runs, residuals, covariates, out);
  // Correlations over few runs are noisy: quote one only above 0.6 and 2/sqrt(runs).
  out.covariate_threshold =
      std::max(0.6, 2.0 / std::sqrt(static_cast<double>(std::max<std::size_t>(runs.size(), 1))));
  return out;
}

std::string ResidualStructure::summary() const {
  std::string out;
  char text[160];
  for (const ExcessBin& b : bins) {
    std::snprintf(text, sizeof text, "%s%s %s (%.0f %% of the excess, mean residual %+.1f mN)",
                  out.empty() ? "" : "; ", b.view.c_str(), b.bin.c_str(), 100.0 * b.share,
                  1000.0 * b.mean_residual_N);
    out += text;
  }
  if (!covariate.empty() && std::abs(covariate_correlation) >= covariate_threshold) {
    std::snprintf(text, sizeof text, "; runs' mean residual tracks %s (r = %+.2f)",
                  covariate.c_str(), covariate_correlation);
    out += text;
  }
  return out.empty() ? "no part of the data stands above the floor" : out;
}

}  // namespace rig::model
