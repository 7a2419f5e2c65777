#pragma once
// One physical or instrument effect the paper's model does not have, as a term the model
// lab can add: its meaning, its parameters with bounds and units, and how it changes the
// prediction. Physical effects have parameters shared by all runs; instrument effects
// (drift, mains phase, ripple phase) also have per-run coefficients, linear in the
// prediction, fitted on each run's own data.
#include <Eigen/Core>

#include <string>
#include <vector>

#include "eye_params.hpp"
#include "force_model.hpp"
#include "prepared_run.hpp"

namespace rig::model {

struct ParamSpec {
  std::string name;
  std::string unit;
  double initial = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};

struct SampleView {
  const PreparedRun* run = nullptr;
  std::size_t i = 0;
  double x_mm = 0.0;
  double t_s = 0.0;
  double force_N = 0.0;  // measured
  double velocity_mm_s = 0.0;
  double hold_s = 0.0;
  double inserted_mm = 0.0;        // blade length past the model's puncture depth
  Phase phase = Phase::kApproach;  // detected from the data (approach, hold, retraction)
  bool after_puncture = false;     // past the model's own x_pi (Eq. 1's phases, for the terms)
  bool cutting = false;            // between the model's x_pi and x_c while inserting
  double x_pi_mm = 0.0;            // the model's puncture depth for this run
  const SampleInputs* inputs =
      nullptr;  // this sample's packed inputs (set by the predictor; else run->inputs[i])
};

// What a term may quote as evidence: its fitted shared parameters, the runs, and each run's
// own coefficients (this term's slice).
struct EvidenceInput {
  const double* shared = nullptr;
  std::vector<const PreparedRun*> runs;
  std::vector<Eigen::VectorXd> run_coefficients;
};

class EffectTerm {
 public:
  virtual ~EffectTerm() = default;
  virtual std::string name() const = 0;
  virtual std::string meaning() const = 0;
  virtual std::vector<ParamSpec> shared_params() const { return {}; }
  virtual int linear_columns() const { return 0; }
  // Linear coefficients per run (instrument effects, default) or shared by all runs.
  virtual bool per_run_coefficients() const { return true; }
  // What the per-run part costs on `run` in an information criterion: its linear columns,
  // unless some are identically 0 there (a step the run does not have).
  virtual int run_parameters(const PreparedRun& /*run*/) const { return linear_columns(); }
  // Whether the data can show this effect at all (e.g. several velocities for a rate term).
  virtual bool applicable(const std::vector<const PreparedRun*>& runs, std::string& why_not) const;

  // Stages of the prediction (see Predictor): model parameters of the run, displacement
  // correction, scale of the tissue force, additive force, per-run linear columns.
  virtual void adjust_model(const PreparedRun& run, const double* p, ContinuousParams& model) const;
  virtual double x_shift(const SampleView& s, const double* p) const;
  // The shift of the deepest point reached so far [mm] (the front Eq. 1's release is measured
  // from): by default the sample's own shift; a mount's lag there is the lag the tip had
  // when the carriage was last at its front, not the lag of the force now.
  virtual double front_shift(const SampleView& s, const double* p) const { return x_shift(s, p); }
  virtual double scale(const SampleView& s, const double* p) const;
  virtual double add(const SampleView& s, const double* p, double force_N) const;
  virtual void design(const SampleView& s, const double* p, double* row) const;

  // Several starting points for the shared parameters (multimodal ones: periods,
  // frequencies); the lab keeps the best before refining.
  virtual std::vector<std::vector<double>> starts() const;
  // Whether the starts must each be fitted (baseline and eyes with them) before one is kept:
  // a start in a valley the baseline's own parameters have to move into looks worse than
  // the others at the baseline's values, and picking by the unfitted error never tries it.
  virtual bool fit_each_start() const { return false; }
  // The evidence in words, from the fitted parameters.
  virtual std::string evidence(const EvidenceInput& in) const = 0;
  // Whether the fitted form can be told apart from a smooth misfit of the baseline over
  // these data (e.g. a period seen repeating); false with the reason when it cannot. Asked
  // after the fit: a candidate that is not identifiable is never a verdict or a partial one.
  virtual bool identifiable(const EvidenceInput& /*fitted*/, std::string& /*why_not*/) const {
    return true;
  }

  // Effect families: a catalogue entry covers the forms its physics uses ("coulomb",
  // "viscous", ...). forms() names them (empty: a single form); form() is this instance's.
  // The catalogue picks the form by an information criterion (see form_selection.hpp).
  virtual std::vector<std::string> forms() const { return {}; }
  virtual std::string form() const { return ""; }

  // Whether this term only scales whole runs by a number fixed per run, which each eye's own
  // tissue scales take up within eyes: then only unseen eyes (the population channel) are
  // evidence for it, and what it gains within eyes is the shared fit less bent by the eyes'
  // differences, which any number that follows them by chance gains too (diagnosis.cpp).
  virtual bool judged_on_unseen_eyes_alone() const { return false; }

  // The shared parameters (fitted values `p`) through which this term sets a run's tissue
  // scale or puncture depth from a number fixed per run (its velocity, IOP, a covariate):
  // they explain part of what would be eye variation, and take that many degrees of freedom
  // from the eyes' spread (eye_params.hpp). Shapes within a run take none.
  virtual EyeDof eye_level_params(const double* /*p*/) const { return {}; }

  // The shared parameters of this term that are linear coefficients of the run's puncture
  // depth on numbers fixed per run (x_pi + sum_j p[index_j] * value_j [mm]): their indices
  // into shared_params(), and `run`'s regressors in the same order into `values`. The lab
  // places such a law from the eyes' own puncture shifts before the fit (puncture_law.hpp):
  // the error is flat in these slopes between fit rows. None by default.
  virtual std::vector<std::size_t> puncture_regressors(const PreparedRun& /*run*/,
                                                       std::vector<double>& values) const {
    values.clear();
    return {};
  }
};

}  // namespace rig::model
