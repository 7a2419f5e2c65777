#include "sensor_drift.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "effect_util.hpp"

namespace rig::model::effects {

const std::vector<std::string>& SensorDrift::form_names() {
  static const std::vector<std::string> kNames = {"polynomial", "thermal", "piecewise-linear",
                                                  "offset steps"};
  return kNames;
}

std::vector<ParamSpec> SensorDrift::shared_params() const {
  if (form_ == kThermal) return {{"tau_drift", "s", 10.0, 0.3, 1000.0}};
  if (form_ == kPiecewiseLinear)
    return {{"knots", kFormLabelUnit, kKnots, kKnots - 0.5, kKnots + 0.5}};
  if (form_ == kOffsetSteps)
    return {{"offset_steps", kFormLabelUnit, kStepColumns, kStepColumns - 0.5, kStepColumns + 0.5}};
  return {};
}

std::vector<std::vector<double>> SensorDrift::starts() const {
  if (form_ != kThermal) return EffectTerm::starts();
  return {{1.0}, {3.0}, {10.0}, {30.0}, {100.0}};
}

int SensorDrift::linear_columns() const {
  if (form_ == kOffsetSteps) return 1 + kStepColumns;
  return form_ == kPiecewiseLinear ? kKnots : (form_ == kThermal ? 2 : 3);
}

namespace {

// Hat function k of `knots` evenly spaced over [t0, t1] at t.
double hat(double t, double t0, double t1, int k, int knots) {
  const double step = std::max(t1 - t0, 1e-6) / (knots - 1);
  return std::max(0.0, 1.0 - std::abs((t - t0) / step - k));
}

}  // namespace

void SensorDrift::design(const SampleView& s, const double* p, double* row) const {
  if (form_ == kThermal) {
    row[0] = 1.0;
    row[1] = -std::expm1(-std::max(s.t_s - s.run->data->t_s.front(), 0.0) / p[0]);
    return;
  }
  if (form_ == kPiecewiseLinear) {
    const auto& t = s.run->data->t_s;
    for (int k = 0; k < kKnots; ++k) row[k] = hat(s.t_s, t.front(), t.back(), k, kKnots);
    return;
  }
  if (form_ == kOffsetSteps) {
    // An offset, and a unit step at each of the run's own offset steps (found on its data by
    // the phase detector); a run with fewer steps leaves the other columns 0.
    row[0] = 1.0;
    const auto& steps = s.run->seg.offset_steps;
    for (int k = 0; k < kStepColumns; ++k) {
      const auto at = static_cast<std::size_t>(k);
      row[1 + k] = at < steps.size() && s.t_s >= steps[at].t_s ? 1.0 : 0.0;
    }
    return;
  }
  const double t = s.t_s / 10.0;  // scaled for conditioning
  row[0] = 1.0;
  row[1] = t;
  row[2] = t * t;
}

int SensorDrift::run_parameters(const PreparedRun& run) const {
  if (form_ != kOffsetSteps) return linear_columns();
  // The offset and each step's size. A step's time is found by the phase detector on the
  // force alone, as the run's puncture and stops are, and like them is no parameter of a form.
  return 1 + static_cast<int>(std::min<std::size_t>(run.seg.offset_steps.size(), kStepColumns));
}

double SensorDrift::drift(const PreparedRun& run, const Eigen::VectorXd& c, const double* p,
                          double t_s) const {
  std::vector<double> row(static_cast<std::size_t>(linear_columns())), first(row.size());
  SampleView s{&run, 0, 0.0, t_s};
  design(s, p, row.data());
  s.t_s = run.data->t_s.front();
  design(s, p, first.data());
  double value = 0.0;
  for (std::size_t k = 0; k < row.size() && static_cast<Eigen::Index>(k) < c.size(); ++k)
    value += c(static_cast<Eigen::Index>(k)) * (row[k] - first[k]);
  return value;
}

std::string SensorDrift::evidence(const EvidenceInput& in) const {
  double worst = 0.0, rate = 0.0;
  for (std::size_t r = 0; r < in.runs.size() && r < in.run_coefficients.size(); ++r) {
    const auto& c = in.run_coefficients[r];
    if (c.size() < linear_columns()) continue;
    const auto& t = in.runs[r]->data->t_s;
    double change = 0.0;
    for (int k = 1; k <= 20; ++k)
      change = std::max(change, std::abs(drift(*in.runs[r], c, in.shared,
                                               t.front() + (t.back() - t.front()) * k / 20.0)));
    if (change > worst) worst = change, rate = change / std::max(t.back() - t.front(), 1e-6);
  }
  if (form_ == kOffsetSteps) return step_evidence(in) + honesty(in);
  std::string shape = "polynomial drift: ";
  if (form_ == kThermal)
    shape = format("thermal drift (first-order warm-up, %.1f s): ", in.shared[0]);
  if (form_ == kPiecewiseLinear) shape = "random-walk-like drift (piecewise-linear per run): ";
  return shape +
         format(
             "the force offset moves by up to %.4f N within a run (about %.2f mN/s), differently "
             "in every run",
             worst, rate * 1e3) +
         honesty(in);
}

std::string SensorDrift::step_evidence(const EvidenceInput& in) const {
  // The largest fitted steps, each with its run and time; then how many runs had one.
  struct Named {
    double size_N, t_s;
    std::size_t run;
  };
  std::vector<Named> steps;
  std::size_t runs_with = 0;
  for (std::size_t r = 0; r < in.runs.size() && r < in.run_coefficients.size(); ++r) {
    const auto& c = in.run_coefficients[r];
    const auto& found = in.runs[r]->seg.offset_steps;
    runs_with += found.empty() ? 0 : 1;
    for (std::size_t k = 0; k < found.size() && k < static_cast<std::size_t>(kStepColumns) &&
                            1 + static_cast<Eigen::Index>(k) < c.size();
         ++k) {
      steps.push_back(
          {c(1 + static_cast<Eigen::Index>(k)), found[k].t_s - in.runs[r]->data->t_s.front(), r});
    }
  }
  std::sort(steps.begin(), steps.end(),
            [](const Named& a, const Named& b) { return std::abs(a.size_N) > std::abs(b.size_N); });
  char text[256];
  if (steps.empty()) {  // the form without a step: a constant per run, said as such
    std::snprintf(text, sizeof text,
                  "offset steps of the load cell's zero: no jump in any of the %zu runs is the "
                  "sensor's, so this form is a constant offset per run",
                  in.runs.size());
    return text;
  }
  std::snprintf(text, sizeof text,
                "offset steps of the load cell's zero, at the jumps found in each run's own force: "
                "%zu in %zu of %zu runs",
                steps.size(), runs_with, in.runs.size());
  std::string out = text;
  for (std::size_t k = 0; k < steps.size() && k < 3; ++k) {
    std::snprintf(text, sizeof text, "%s offset step of %+.1f mN at %.1f s in run %zu (%s)",
                  k == 0 ? ";" : ",", steps[k].size_N * 1e3, steps[k].t_s, steps[k].run + 1,
                  in.runs[steps[k].run]->label().c_str());
    out += text;
  }
  return out;
}

}  // namespace rig::model::effects
