#pragma once
// The explainer's library of candidate features, SINDy-style: simple functions of what a
// user term sees (depth, inserted length, velocity, time, time in hold, the model's force,
// IOP, run covariates) times a phase gate (all, insertion, precut, cutting, hold,
// retraction). Every feature is a muParser expression in the user-term variables and is
// evaluated by muParser itself, so a selected feature means exactly what the proposed term
// computes.
#include <muParser.h>

#include <memory>
#include <string>
#include <vector>

#include "sample_probe.hpp"

namespace rig::model::explainer {

struct Feature {
  std::string expression;  // in the user-term variables, e.g. "x^2", "(blade_uses-4.5)*x"
  std::string gate;        // the phase it is confined to, as a user term's phase
  std::size_t base = 0;    // index of its expression in the library's base list
  std::string label() const { return gate == "all" ? expression : expression + " [" + gate + "]"; }
};

struct Covariate {
  std::string key;    // metadata key or channel, a valid muParser name
  double mean = 0.0;  // over the runs: features use (key - mean) so they do not copy a constant
};

class FeatureLibrary {
 public:
  // `holds`: whether any run has a hold (features of time in hold need one).
  FeatureLibrary(const std::vector<Covariate>& covariates, bool holds);
  FeatureLibrary(const FeatureLibrary&) = delete;
  FeatureLibrary& operator=(const FeatureLibrary&) = delete;

  const std::vector<Feature>& features() const { return features_; }
  // One row of feature values for a sample; `covariates` in the constructor's order.
  void row(const ProbedSample& s, const double* covariates, double* out) const;

  static const std::vector<std::string>& gates();
  static bool usable_name(const std::string& key);  // a muParser variable name, not a user-term one

 private:
  void add_base(const std::string& expression, bool hold_only);

  std::vector<Feature> features_;
  std::vector<std::size_t> gate_of_;               // per feature: index into gates()
  std::vector<std::unique_ptr<mu::Parser>> base_;  // one parser per base expression
  mutable double x_ = 0, t_ = 0, v_ = 0, p_ = 0, f_ = 0, l_ = 0, th_ = 0;
  mutable std::vector<double> covariate_values_;
  std::vector<std::string> covariate_keys_;
  mutable std::vector<double> base_values_;
};

}  // namespace rig::model::explainer
