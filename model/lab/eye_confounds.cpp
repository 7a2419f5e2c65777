#include "eye_confounds.hpp"

#include <cmath>
#include <cstdio>
#include <optional>

#include "correlation.hpp"

namespace rig::model {
namespace {

constexpr double kStrongCorrelation = 0.9;  // by chance over 9 runs: p ~ 0.001 per pair
constexpr std::size_t kMinRuns = 6;
constexpr double kOwnEyeFarAbove = 5.0;       // x the measurement noise
constexpr double kPopulationNearFloor = 1.6;  // x the floor

struct RunVariable {
  std::string name;
  std::vector<double> values;  // per run
};

std::vector<RunVariable> run_variables(const std::vector<const PreparedRun*>& runs,
                                       const std::vector<std::string>& keys) {
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

std::vector<std::string> eye_confound_warnings(const std::vector<const PreparedRun*>& runs,
                                               const std::vector<EyeParams>& eyes,
                                               const std::vector<std::string>& covariate_keys) {
  std::vector<std::string> warnings;
  if (runs.size() < kMinRuns || eyes.size() != runs.size()) return warnings;
  const std::pair<const char*, double EyeParams::*> parameters[] = {
      {"puncture depth", &EyeParams::x_pi_mm},
      {"pre-cut force scale", &EyeParams::precut_scale},
      {"cutting force scale", &EyeParams::cut_scale}};
  const std::vector<RunVariable> variables = run_variables(runs, covariate_keys);
  for (const auto& [label, member] : parameters) {
    std::vector<double> per_eye;
    per_eye.reserve(eyes.size());
    for (const EyeParams& e : eyes) per_eye.push_back(e.*member);
    for (const RunVariable& v : variables) {
      const double r = correlation(per_eye, v.values);  // 0 when either is constant
      if (std::abs(r) < kStrongCorrelation) continue;
      char text[320];
      std::snprintf(text, sizeof text,
                    "the eyes' %s follows %s (r = %+.2f over %zu runs): what the floor counts as "
                    "eye variation may be an effect "
                    "of %s, and the floor too high to name it",
                    label, v.name.c_str(), r, runs.size(), v.name.c_str());
      warnings.emplace_back(text);
    }
  }
  return warnings;
}

std::optional<std::string> inflated_floor_warning(const FloorReading& b) {
  const bool structure_within_eyes = b.own_eye_cv_N >= kOwnEyeFarAbove * b.measurement_N;
  const bool population_near_floor = b.population_cv_N <= kPopulationNearFloor * b.floor_N;
  const bool floor_is_eyes = b.eye_variation_N > b.measurement_N;
  if (b.measurement_N <= 0.0 || b.floor_N <= 0.0 || !structure_within_eyes ||
      !population_near_floor || !floor_is_eyes) {
    return std::nullopt;
  }
  char text[400];
  std::snprintf(
      text, sizeof text,
      "within eyes the CV error is %.1fx the measurement noise, yet across eyes only %.2fx its "
      "floor, of which eye "
      "variation is %.1f mN and noise %.1f mN: the eyes' own scales and puncture depths may have "
      "absorbed an effect, so "
      "read the floor as an upper bound and the candidates' gains across eyes as understated",
      b.own_eye_cv_N / b.measurement_N, b.population_cv_N / b.floor_N, 1e3 * b.eye_variation_N,
      1e3 * b.measurement_N);
  return std::string(text);
}

namespace {
// The relative standard error of an SD estimated from one value per eye (chi-square).
double eye_part_uncertainty(std::size_t eyes) {
  return 1.0 / std::sqrt(2.0 * static_cast<double>(eyes - 1));
}
}  // namespace

double plausible_floor(const FloorReading& b, std::size_t eyes) {
  if (eyes < 2) return b.floor_N;
  const double up = 1.0 + eye_part_uncertainty(eyes);
  const double eye_N = b.eye_variation_N * up;
  return std::sqrt(b.measurement_N * b.measurement_N + eye_N * eye_N);
}

std::optional<std::string> uncertain_floor_warning(const FloorReading& b, std::size_t eyes,
                                                   double well_above, double own_eye_well_above) {
  const double highest_N = plausible_floor(b, eyes);
  const bool above_estimate = b.population_cv_N > well_above * b.floor_N;
  const bool within_plausible = b.population_cv_N <= well_above * highest_N;
  const bool quiet_within_eyes = b.own_eye_cv_N < own_eye_well_above * b.measurement_N;
  if (eyes < 2 || b.floor_N <= 0.0 || !above_estimate || !within_plausible || !quiet_within_eyes)
    return std::nullopt;
  char text[400];
  std::snprintf(text, sizeof text,
                "across eyes the CV error is %.2fx a floor of %.1f mN whose eye part comes from "
                "%zu eyes and is known to about "
                "+-%.0f %%: a floor of up to %.1f mN is plausible, and %.2fx that is not well "
                "above it; with more eyes, read "
                "`unexplained` as structure only if it stays",
                b.population_cv_N / b.floor_N, 1e3 * b.floor_N, eyes,
                100.0 * eye_part_uncertainty(eyes), 1e3 * highest_N, b.population_cv_N / highest_N);
  return std::string(text);
}

}  // namespace rig::model
