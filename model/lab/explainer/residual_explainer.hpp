#pragma once
// The explainer of structure no catalogue effect names (in the spirit of SINDy): the
// baseline's cross-validated residuals are regressed on a library of candidate features
// (FeatureLibrary) with sparse selection (LassoPath) and cross-validation over runs; the
// selected features become a closed-form user term, which is then fitted with the model
// and cross-validated like any effect. `explain` is the whole thing from runs; `diagnose`
// callers that already have the baseline's CV use the class directly.
#include <vector>

#include "cross_validation.hpp"
#include "explanation.hpp"
#include "feature_library.hpp"
#include "lasso_path.hpp"
#include "model_family.hpp"

namespace rig::model::explainer {

class ResidualExplainer {
 public:
  // base: the baseline family (model file's effects + options.with); base_cv: its CV on runs.
  ResidualExplainer(const ForceModel& model, const ModelFamily& base,
                    std::vector<const PreparedRun*> runs, const CvResult& base_cv,
                    ExplainOptions options);
  Explanation explain() const;

 private:
  struct RunRows {
    std::vector<std::size_t> rows;      // sample indices
    std::vector<double> residual;       // baseline CV residual there [N]
    std::vector<ProbedSample> samples;  // what a user term sees there
    std::vector<double> covariates;     // rows x covariates, row-major
  };
  struct Design {
    std::vector<GramStats> groups;
    std::vector<int> fold_of;
    std::vector<double> scale;  // column RMS: standardised = raw / scale
    std::size_t group_per_run = 1;
  };

  std::vector<Covariate> covariates() const;
  RunRows sample_run(std::size_t r, const std::vector<Covariate>& covariates) const;
  Design design(const FeatureLibrary& library, const std::vector<RunRows>& rows) const;
  static Eigen::VectorXd standardise(const GramStats& all, std::vector<double>& scale);
  void describe(const FeatureLibrary& library, const Design& d, const LassoPath& path,
                const PathStep& s, Explanation& e) const;
  void validate(Explanation& e) const;
  std::string free_name() const;

  const ForceModel* model_;
  const ModelFamily* base_;
  std::vector<const PreparedRun*> runs_;
  const CvResult* base_cv_;
  ExplainOptions options_;
};

// From runs alone: prepares them, fits and cross-validates the baseline (the model file's
// effects + options.with), then explains what remains.
Explanation explain(const ForceModel& model, const std::vector<RunData>& runs,
                    const ExplainOptions& options = {});

}  // namespace rig::model::explainer
