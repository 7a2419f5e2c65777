#include "eye_confounds.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

#include "correlation.hpp"

namespace rig::model {
namespace {

constexpr double kStrongCorrelation = 0.9;  // by chance over 9 runs: p ~ 0.001 per pair
constexpr std::size_t kMinRuns = 6;

struct RunVariable {
  std::string name;
  std::vector<double> values;  // per run
};

std::vector<RunVariable> run_variables(const std::vector<const PreparedRun*>& runs, const std::vector<std::string>& keys) {
  std::vector<RunVariable> out{{"the speed", {}}, {"the IOP", {}}};
  bool iop_known = true;
  for (const PreparedRun* r : runs) {
    out[0].values.push_back(r->velocity_cmd_mm_s);
    out[1].values.push_back(r->iop_mmHg);
    iop_known = iop_known && r->iop_known;
  }
  if (!iop_known) out.pop_back();
  for (const std::string& key : keys) {
    RunVariable v{key, {}};
    for (const PreparedRun* r : runs) {
      const std::optional<double> value = r->covariate(key, 0);
      if (!value) break;
      v.values.push_back(*value);
    }
    if (v.values.size() == runs.size()) out.push_back(std::move(v));
  }
  return out;
}

}  // namespace

std::vector<std::string> eye_confound_warnings(const std::vector<const PreparedRun*>& runs, const std::vector<EyeParams>& eyes,
                                               const std::vector<std::string>& covariate_keys) {
  std::vector<std::string> warnings;
  if (runs.size() < kMinRuns || eyes.size() != runs.size()) return warnings;
  const std::pair<const char*, double EyeParams::*> parameters[] = {
      {"puncture depth", &EyeParams::x_pi_mm}, {"pre-cut force scale", &EyeParams::precut_scale}, {"cutting force scale", &EyeParams::cut_scale}};
  for (const auto& [label, member] : parameters) {
    std::vector<double> per_eye;
    for (const EyeParams& e : eyes) per_eye.push_back(e.*member);
    for (const RunVariable& v : run_variables(runs, covariate_keys)) {
      const double r = correlation(per_eye, v.values);  // 0 when either is constant
      if (std::abs(r) < kStrongCorrelation) continue;
      char text[320];
      std::snprintf(text, sizeof text,
                    "the eyes' %s follows %s (r = %+.2f over %zu runs): what the floor counts as eye variation may be an effect "
                    "of %s, and the floor too high to name it",
                    label, v.name.c_str(), r, runs.size(), v.name.c_str());
      warnings.emplace_back(text);
    }
  }
  return warnings;
}

}  // namespace rig::model
