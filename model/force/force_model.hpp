#pragma once
// The keratome-cornea force model: Eq. 1 of the seed paper, as printed or in our
// continuous interpretation, with x_pi and x_pf interpolated in IOP from Table 1. A model
// file may also carry the effects and user terms the model lab added (their shared
// parameters); those are evaluated by the lab's Predictor, not here.
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rig::model {

class ModelFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

enum class ModelForm { kPrinted, kContinuous };

struct IopTable {
  std::vector<double> iop_mmHg{15, 16, 17, 18};
  std::vector<double> x_pi_mm{3.55, 3.75, 3.96, 4.30};
  std::vector<double> x_pf_mm{9.35, 9.55, 9.83, 10.03};
  // Linear interpolation; outside the table the end segments are extended and
  // `extrapolated` is set (callers warn).
  double interpolate(const std::vector<double>& values, double iop,
                     bool* extrapolated = nullptr) const;
};

// Our continuous interpretation (docs/model.md).
struct ContinuousParams {
  double a = 0.0066, x1 = 0.75, b = 0.078;
  double d = -0.004, e = 3.282, f = -0.495, g = 0.02, g0 = -0.114;
  double x_c = 6.89, w_drop = 0.05;
  double w_release = 0.2;  // withdrawal over which the force at the deepest point is released [mm]
  double x_pi_shift = 0.0, x_pf_shift = 0.0;  // fitted shifts of the Table-1 depths [mm]
};

// The printed parameter list, names and values as printed.
struct PrintedParams {
  std::vector<std::string> names;
  std::vector<double> values;
  double x_toe_end_mm = 0.75, x_cut_end_mm = 6.89, x_end_mm = 14.0;
  double value(const std::string& name) const;  // positional reading; a missing value is 0
  bool has(const std::string& name) const;
};

struct EffectSetting {
  std::string name;                      // catalogue name, covariate:KEY or user:NAME
  std::map<std::string, double> params;  // shared parameters
};

struct UserTerm {
  std::string name;
  std::string expression;  // muParser: x, t, v, P, F, L, th, is_PHASE, covariates, params
  std::string phase;       // insertion, cutting, precut, hold, retraction, all
  std::map<std::string, double> params;  // initial values, refitted by the lab
};

class ForceModel {
 public:
  static ForceModel load(const std::string& path);
  static ForceModel paper_interpreted();
  void save(const std::string& path) const;

  // Insertion force at depth x [mm] from the corneal surface for an IOP [mmHg] [N].
  double baseline(double x_mm, double iop_mmHg) const;
  // Force with the blade at x after reaching `front` [mm]: held at depth it keeps the force
  // reached there, withdrawn it releases it over w_release (continuous form only).
  double baseline(double x_mm, double front_mm, double iop_mmHg) const;
  double puncture_depth_mm(double iop_mmHg) const;
  double final_depth_mm(double iop_mmHg) const;
  bool extrapolates(double iop_mmHg) const;

  // One run's IOP and the depths it sets, looked up once: a fit evaluates a run at hundreds
  // of rows, and the two table lookups per row were a tenth of a diagnosis' time.
  struct RunDepths {
    double iop_mmHg = 15.0;
    double x_pi_mm = 0.0;  // puncture depth (with the fitted shift)
    double x_pf_mm = 0.0;  // final depth of the cut (with the fitted shift)
  };
  RunDepths depths(double iop_mmHg) const;
  // As baseline(x, front, iop), with the run's depths looked up before.
  double baseline(double x_mm, double front_mm, const RunDepths& run) const;

  std::string name = "paper-interpreted";
  std::string path;
  ModelForm form = ModelForm::kContinuous;
  double reference_velocity_mm_s = 2.0;
  IopTable table;
  ContinuousParams params;
  PrintedParams printed;
  std::vector<EffectSetting> effects;
  std::vector<UserTerm> user_terms;  // part of the model: always fitted, saved in [terms]
  // Terms offered but not (yet) part of the model (`--terms FILE`): diagnose scores them as
  // candidates, `fit --add user:NAME` adds them. Never saved with the model.
  std::vector<UserTerm> candidate_terms;

 private:
  double continuous(double x_mm, const RunDepths& run) const;
  double as_printed(double x_mm, double iop_mmHg) const;
};

// A term file: only [terms.NAME] tables, as in a model file (errors name file, line, key).
std::vector<UserTerm> load_user_terms(const std::string& path);
void save_user_terms(const std::string& path, const std::vector<UserTerm>& terms);

// Value of the Stribeck-like cutting plateau of the continuous form [N].
double cutting_plateau(const ContinuousParams& p, double x_mm, double iop_mmHg);

}  // namespace rig::model
