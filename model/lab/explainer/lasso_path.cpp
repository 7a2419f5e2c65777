#include "lasso_path.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace rig::model::explainer {
namespace {

constexpr int kMaxSweeps = 200;
constexpr double kTolerance = 1e-7;  // largest coefficient change per sweep, standardised units
constexpr double kSmallestLambda = 1e-3;  // of the largest useful lambda

double soft(double z, double lambda) {
  return z > lambda ? z - lambda : (z < -lambda ? z + lambda : 0.0);
}

// Coordinate descent for (1/2n)|y - X b|^2 + lambda |b|_1, from b (warm start).
void lasso(const GramStats& s, double lambda, Eigen::VectorXd& b) {
  const Eigen::Index p = s.xtx.cols();
  const double n = std::max(s.n, 1.0);
  Eigen::VectorXd gb = s.xtx * b;  // X'X b, kept up to date
  for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
    double largest = 0.0;
    for (Eigen::Index j = 0; j < p; ++j) {
      const double gjj = s.xtx(j, j);
      if (gjj <= 0.0) continue;
      const double z = (s.xty(j) - gb(j) + gjj * b(j)) / n;
      const double updated = soft(z, lambda) / (gjj / n);
      const double delta = updated - b(j);
      if (delta == 0.0) continue;
      gb += delta * s.xtx.col(j);
      b(j) = updated;
      largest = std::max(largest, std::abs(delta));
    }
    if (largest < kTolerance) break;
  }
}

std::vector<int> support_of(const Eigen::VectorXd& b) {
  std::vector<int> out;
  for (Eigen::Index j = 0; j < b.size(); ++j) {
    if (b(j) != 0.0) out.push_back(static_cast<int>(j));
  }
  return out;
}

// Least squares on the support (a whisker of ridge keeps collinear columns harmless).
Eigen::VectorXd refit(const GramStats& s, const std::vector<int>& support) {
  const auto k = static_cast<Eigen::Index>(support.size());
  Eigen::MatrixXd a(k, k);
  Eigen::VectorXd c(k);
  for (Eigen::Index i = 0; i < k; ++i) {
    c(i) = s.xty(support[static_cast<std::size_t>(i)]);
    for (Eigen::Index j = 0; j < k; ++j)
      a(i, j) = s.xtx(support[static_cast<std::size_t>(i)], support[static_cast<std::size_t>(j)]);
  }
  a.diagonal().array() += 1e-8 * std::max(s.n, 1.0);
  return a.ldlt().solve(c);
}

double held_out_sse(const GramStats& s, const std::vector<int>& support, const Eigen::VectorXd& b) {
  double sse = s.yty;
  for (std::size_t i = 0; i < support.size(); ++i) {
    const auto bi = b(static_cast<Eigen::Index>(i));
    sse -= 2.0 * bi * s.xty(support[i]);
    for (std::size_t j = 0; j < support.size(); ++j)
      sse += bi * b(static_cast<Eigen::Index>(j)) * s.xtx(support[i], support[j]);
  }
  return std::max(sse, 0.0);
}

}  // namespace

void GramStats::add(const GramStats& other) {
  if (xtx.size() == 0) {
    *this = other;
    return;
  }
  xtx += other.xtx;
  xty += other.xty;
  yty += other.yty;
  n += other.n;
}

LassoPath::LassoPath(const std::vector<GramStats>& groups, const std::vector<int>& fold_of,
                     int max_features, int steps)
    : groups_(groups), fold_of_(fold_of) {
  for (const GramStats& g : groups) all_.add(g);
  for (const GramStats& g : groups) empty_sse_ += g.yty;
  if (groups.empty() || all_.xty.size() == 0) return;
  const GramStats& all = all_;
  const int folds = *std::max_element(fold_of.begin(), fold_of.end()) + 1;
  train_.resize(static_cast<std::size_t>(folds));
  for (int f = 0; f < folds; ++f) {
    for (std::size_t g = 0; g < groups.size(); ++g) {
      if (fold_of[g] != f) train_[static_cast<std::size_t>(f)].add(groups[g]);
    }
  }
  const std::vector<GramStats>& train = train_;
  const double lambda_max = all.xty.cwiseAbs().maxCoeff() / std::max(all.n, 1.0);
  Eigen::VectorXd b_all = Eigen::VectorXd::Zero(all.xty.size());
  std::vector<Eigen::VectorXd> b_fold(static_cast<std::size_t>(folds), b_all);
  for (int k = 1; k < steps; ++k) {
    PathStep step;
    step.lambda = lambda_max * std::pow(kSmallestLambda, static_cast<double>(k) / (steps - 1));
    lasso(all, step.lambda, b_all);
    step.support = support_of(b_all);
    if (static_cast<int>(step.support.size()) > max_features) break;
    if (step.support.empty()) continue;
    step.coefficients = refit(all, step.support);
    step.group_cv_sse.assign(groups.size(), 0.0);
    for (int f = 0; f < folds; ++f) {
      Eigen::VectorXd& b = b_fold[static_cast<std::size_t>(f)];
      const GramStats& t = train[static_cast<std::size_t>(f)];
      if (t.n <= 0.0) continue;
      lasso(t, step.lambda, b);
      const std::vector<int> support = support_of(b);
      const Eigen::VectorXd coefficients = support.empty() ? Eigen::VectorXd() : refit(t, support);
      for (std::size_t g = 0; g < groups.size(); ++g) {
        if (fold_of[g] == f) step.group_cv_sse[g] = held_out_sse(groups[g], support, coefficients);
      }
    }
    for (const double sse : step.group_cv_sse) step.cv_sse += sse;
    steps_.push_back(std::move(step));
  }
}

std::vector<double> LassoPath::group_empty_sse() const {
  std::vector<double> out;
  for (const GramStats& g : groups_) out.push_back(g.yty);
  return out;
}

int LassoPath::choose(double share) const {
  int best = -1;
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    if (steps_[k].cv_sse < empty_sse_ &&
        (best < 0 || steps_[k].cv_sse < steps_[static_cast<std::size_t>(best)].cv_sse))
      best = static_cast<int>(k);
  }
  if (best < 0) return -1;
  const double needed = share * (empty_sse_ - steps_[static_cast<std::size_t>(best)].cv_sse);
  int chosen = best;
  for (std::size_t k = 0; k < steps_.size(); ++k) {
    const PathStep& s = steps_[k];
    if (empty_sse_ - s.cv_sse < needed) continue;
    const PathStep& c = steps_[static_cast<std::size_t>(chosen)];
    if (s.support.size() < c.support.size() ||
        (s.support.size() == c.support.size() && s.cv_sse < c.cv_sse))
      chosen = static_cast<int>(k);
  }
  return chosen;
}

PathStep LassoPath::with_support(const std::vector<int>& support) const {
  PathStep step;
  step.support = support;
  step.coefficients = support.empty() ? Eigen::VectorXd() : refit(all_, support);
  step.group_cv_sse.assign(groups_.size(), 0.0);
  for (std::size_t f = 0; f < train_.size(); ++f) {
    if (train_[f].n <= 0.0) continue;
    const Eigen::VectorXd coefficients =
        support.empty() ? Eigen::VectorXd() : refit(train_[f], support);
    for (std::size_t g = 0; g < groups_.size(); ++g) {
      if (fold_of_[g] == static_cast<int>(f))
        step.group_cv_sse[g] = held_out_sse(groups_[g], support, coefficients);
    }
  }
  for (const double sse : step.group_cv_sse) step.cv_sse += sse;
  return step;
}

PathStep LassoPath::prune(const PathStep& step, double min_share) const {
  PathStep current = with_support(step.support);
  while (current.support.size() > 1) {
    const double gain = empty_sse_ - current.cv_sse;
    std::size_t weakest = 0;
    double weakest_loss = INFINITY;
    for (std::size_t k = 0; k < current.support.size(); ++k) {
      std::vector<int> without = current.support;
      without.erase(without.begin() + static_cast<std::ptrdiff_t>(k));
      const double loss = with_support(without).cv_sse - current.cv_sse;  // what feature k is worth
      if (loss < weakest_loss) weakest_loss = loss, weakest = k;
    }
    if (weakest_loss >= min_share * gain) break;
    std::vector<int> without = current.support;
    without.erase(without.begin() + static_cast<std::ptrdiff_t>(weakest));
    current = with_support(without);
  }
  current.lambda = step.lambda;
  return current;
}

}  // namespace rig::model::explainer
