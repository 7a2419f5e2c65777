#pragma once
// Sparse selection for the explainer: the LASSO path by coordinate descent on Gram matrices
// (covariance updates: nothing but X'X, X'y and y'y per group of rows is ever needed), each
// support refitted by least squares (relaxed LASSO), with cross-validation over groups of
// rows (runs): every step's support and coefficients come from the training groups alone
// and are scored on the held-out ones. Columns are expected standardised.
#include <Eigen/Core>

#include <vector>

namespace rig::model::explainer {

// X'X, X'y, y'y and the row count of one group of rows (a run, or a chunk of one run).
struct GramStats {
  Eigen::MatrixXd xtx;
  Eigen::VectorXd xty;
  double yty = 0.0;
  double n = 0.0;
  void add(const GramStats& other);
};

struct PathStep {
  double lambda = 0.0;
  std::vector<int> support;          // selected columns on all groups
  Eigen::VectorXd coefficients;      // least squares on the support, all groups
  double cv_sse = 0.0;               // held-out SSE summed over the folds
  std::vector<double> group_cv_sse;  // per group, held out
};

class LassoPath {
 public:
  // fold_of[g]: the fold in which group g is held out (0..folds-1). Steps with more than
  // max_features columns are not kept.
  LassoPath(const std::vector<GramStats>& groups, const std::vector<int>& fold_of, int max_features,
            int steps = 40);

  const std::vector<PathStep>& steps() const { return steps_; }
  double empty_sse() const { return empty_sse_; }  // held-out SSE of no feature at all (sum y'y)
  std::vector<double> group_empty_sse() const;
  // The sparsest step whose CV gain is at least `share` of the best step's; -1 if no step
  // lowers the held-out error.
  int choose(double share = 0.95) const;
  // A step with fewer features: while some feature carries less than `min_share` of the
  // step's held-out gain (the CV error rises by less without it), it is dropped.
  PathStep prune(const PathStep& step, double min_share) const;
  // The cross-validated least-squares fit of a given support.
  PathStep with_support(const std::vector<int>& support) const;

 private:
  std::vector<GramStats> groups_;
  std::vector<int> fold_of_;
  GramStats all_;
  std::vector<GramStats> train_;  // per fold: every group but the held-out ones
  std::vector<PathStep> steps_;
  double empty_sse_ = 0.0;
};

}  // namespace rig::model::explainer
