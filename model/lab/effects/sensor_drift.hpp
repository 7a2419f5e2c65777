#pragma once
// sensor_drift: the load-cell offset wanders during a run, differently in every run, so
// its shape has per-run coefficients fitted on each run's own data. The family:
//   polynomial         offset + slope t + curvature t^2
//   thermal            offset + A (1 - exp(-t/tau)), tau shared (first-order warm-up)
//   piecewise-linear   a hat-function spline with 6 knots over the run (random-walk-like)
//   offset steps       offset + a step at each of the run's own offset steps, found on its
//                      data (level_shifts.hpp: up to 3, where the zero jumped)
#include "family_term.hpp"

namespace rig::model::effects {

class SensorDrift final : public FamilyTerm {
 public:
  enum Form { kPolynomial = 0, kThermal, kPiecewiseLinear, kOffsetSteps };
  static constexpr int kKnots = 6;
  // Steps a run can have: as many as the detector keeps (more are a process, not steps).
  static constexpr int kStepColumns = static_cast<int>(LevelShiftOptions{}.max_steps);
  explicit SensorDrift(int form = kPolynomial) : FamilyTerm(form_names(), form) {}
  static const std::vector<std::string>& form_names();
  std::string name() const override { return "sensor_drift"; }
  std::string meaning() const override {
    return "load-cell offset drifting with time during a run (instrument)";
  }
  std::vector<ParamSpec> shared_params() const override;
  std::vector<std::vector<double>> starts() const override;
  int linear_columns() const override;
  int run_parameters(const PreparedRun& run) const override;
  void design(const SampleView& s, const double* p, double* row) const override;
  std::string evidence(const EvidenceInput& in) const override;
  // The drift of a run with coefficients c at time t [N] (0 at the first sample).
  double drift(const PreparedRun& run, const Eigen::VectorXd& c, const double* p, double t_s) const;

 private:
  // "offset step of +8.1 mN at 7.3 s in run 3 (E07), ..." for the step form.
  std::string step_evidence(const EvidenceInput& in) const;
};

}  // namespace rig::model::effects
