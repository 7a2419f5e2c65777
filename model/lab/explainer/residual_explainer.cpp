#include "residual_explainer.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "diagnosis.hpp"
#include "sample_probe.hpp"

namespace rig::model::explainer {
namespace {

constexpr double kMinGainPct = 5.0;  // as diagnose: below this, structure the model must not chase
constexpr double kMinRunsImproved = 0.6;   // as diagnose: most held-out runs must be better
constexpr int kMaxFolds = 5;               // leave-runs-out folds, as the lab's CV
constexpr std::size_t kChunksOneRun = 50;  // one run: interleaved chunks (~0.3 s) are the CV groups
constexpr double kSameColumn = 0.9999;     // cosine above which two feature columns are one
constexpr double kMinFeatureShare =
    0.05;  // of the held-out gain, that every feature of a term must carry

std::string number(const char* format, double value) {
  char text[48];
  std::snprintf(text, sizeof text, format, value);
  return text;
}

double gain_pct(double before, double after) {
  return before > 0.0 ? 100.0 * (1.0 - after / before) : 0.0;
}

double fraction_improved(const std::vector<double>& before, const std::vector<double>& after) {
  std::size_t better = 0;
  for (std::size_t r = 0; r < before.size(); ++r) better += after[r] < 0.995 * before[r] ? 1U : 0U;
  return before.empty() ? 0.0 : static_cast<double>(better) / static_cast<double>(before.size());
}

std::string term_part(const std::string& parameter, const Feature& f, bool gated) {
  std::string out = parameter;
  if (gated && f.gate != "all") out += "*is_" + f.gate;
  if (f.expression != "1") out += "*" + f.expression;
  return out;
}

}  // namespace

ResidualExplainer::ResidualExplainer(const ForceModel& model, const ModelFamily& base,
                                     std::vector<const PreparedRun*> runs, const CvResult& base_cv,
                                     ExplainOptions options)
    : model_(&model),
      base_(&base),
      runs_(std::move(runs)),
      base_cv_(&base_cv),
      options_(std::move(options)) {
  if (runs_.empty() || base_cv_->residuals.size() != runs_.size())
    throw std::invalid_argument("explain: the baseline's CV residuals do not match the runs");
  const std::string& name = options_.term_name;
  const bool plain = !name.empty() && std::isdigit(static_cast<unsigned char>(name[0])) == 0 &&
                     std::all_of(name.begin(), name.end(), [](char c) {
                       return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
                     });
  if (!plain)
    throw std::invalid_argument("explain: term name '" + name +
                                "': use letters, digits and _ (not first a digit)");
}

std::vector<Covariate> ResidualExplainer::covariates() const {
  const EffectCatalogue catalogue(*model_, runs_);
  std::vector<Covariate> out;
  for (const std::string& name : catalogue.candidates()) {
    if (name.rfind("covariate:", 0) != 0 || !FeatureLibrary::usable_name(name.substr(10))) continue;
    const std::string key = name.substr(10);
    double sum = 0.0;
    double n = 0.0;
    for (const PreparedRun* run : runs_) {
      if (run->analysed.empty()) continue;
      sum += run->covariate(key, run->analysed[run->analysed.size() / 2])
                 .value_or(0.0);  // the run's typical value
      n += 1.0;
    }
    out.push_back({key, n > 0.0 ? sum / n : 0.0});
  }
  return out;
}

ResidualExplainer::RunRows ResidualExplainer::sample_run(
    std::size_t r, const std::vector<Covariate>& covariates) const {
  const PreparedRun& run = *runs_[r];
  RunRows out;
  const std::size_t n = run.analysed.size();
  const std::size_t stride =
      std::max<std::size_t>(1, n / std::max<std::size_t>(options_.rows_per_run, 1));
  for (std::size_t k = 0; k < n; k += stride) {
    out.rows.push_back(run.analysed[k]);
    out.residual.push_back(base_cv_->residuals[r][k]);
  }
  // The baseline with a probe that records what a user term would see at these rows.
  const SampleProbe probe;
  std::vector<const EffectTerm*> terms = base_->predictor().terms();
  terms.push_back(&probe);
  const Predictor predictor(base_->predictor().model(), terms);
  ModelParams params = base_cv_->full.params;
  params.shared.emplace_back();
  std::vector<double> ignored;
  predictor.evaluate(run, params, out.rows, ignored);
  out.samples = probe.take();
  out.samples.resize(
      out.rows.size());  // a second pass (shared linear columns) records the rows again
  for (const std::size_t i : out.rows) {
    for (const Covariate& c : covariates)
      out.covariates.push_back(run.covariate(c.key, i).value_or(0.0));
  }
  return out;
}

ResidualExplainer::Design ResidualExplainer::design(const FeatureLibrary& library,
                                                    const std::vector<RunRows>& rows) const {
  const auto p = static_cast<Eigen::Index>(library.features().size());
  Design d;
  const bool one_run = rows.size() == 1;
  d.group_per_run = one_run ? kChunksOneRun : 1;
  const std::size_t folds = one_run ? kMaxFolds : std::min<std::size_t>(kMaxFolds, rows.size());
  std::vector<double> line(static_cast<std::size_t>(p));
  GramStats all;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const std::size_t m = rows[r].rows.size();
    const std::size_t per_row = m > 0 ? rows[r].covariates.size() / m : 0;
    Eigen::MatrixXd x(static_cast<Eigen::Index>(m), p);
    for (std::size_t k = 0; k < m; ++k) {
      library.row(rows[r].samples[k], rows[r].covariates.data() + k * per_row, line.data());
      x.row(static_cast<Eigen::Index>(k)) = Eigen::Map<const Eigen::RowVectorXd>(line.data(), p);
    }
    const Eigen::Map<const Eigen::VectorXd> y(rows[r].residual.data(),
                                              static_cast<Eigen::Index>(m));
    for (std::size_t c = 0; c < d.group_per_run; ++c) {
      const auto begin = static_cast<Eigen::Index>(c * m / d.group_per_run);
      const auto end = static_cast<Eigen::Index>((c + 1) * m / d.group_per_run);
      const auto block = x.middleRows(begin, end - begin);
      const auto target = y.segment(begin, end - begin);
      d.groups.push_back({block.transpose() * block, block.transpose() * target,
                          target.squaredNorm(), static_cast<double>(end - begin)});
      d.fold_of.push_back(static_cast<int>((one_run ? c : r) % folds));
      all.add(d.groups.back());
    }
  }
  const Eigen::VectorXd inverse = standardise(all, d.scale);
  for (GramStats& g : d.groups) {
    g.xtx = inverse.asDiagonal() * g.xtx * inverse.asDiagonal();
    g.xty = inverse.asDiagonal() * g.xty;
  }
  return d;
}

// Column scales (RMS over all rows) into `scale`; the returned factors standardise, and are
// 0 for a column that is zero everywhere or duplicates an earlier one on these data (L^2
// while inserting is L^2 after the puncture: L is 0 before it) - the earlier, narrower
// gate is kept.
Eigen::VectorXd ResidualExplainer::standardise(const GramStats& all, std::vector<double>& scale) {
  const Eigen::Index p = all.xtx.cols();
  Eigen::VectorXd inverse = Eigen::VectorXd::Zero(p);
  scale.assign(static_cast<std::size_t>(p), 1.0);
  for (Eigen::Index j = 0; j < p; ++j) {
    const double rms = std::sqrt(all.xtx(j, j) / std::max(all.n, 1.0));
    if (rms <= 1e-12) continue;
    bool duplicate = false;
    for (Eigen::Index i = 0; i < j && !duplicate; ++i) {
      duplicate = inverse(i) > 0.0 &&
                  std::abs(all.xtx(i, j)) > kSameColumn * std::sqrt(all.xtx(i, i) * all.xtx(j, j));
    }
    if (duplicate) continue;
    scale[static_cast<std::size_t>(j)] = rms;
    inverse(j) = 1.0 / rms;
  }
  return inverse;
}

void ResidualExplainer::describe(const FeatureLibrary& library, const Design& d,
                                 const LassoPath& path, const PathStep& s, Explanation& e) const {
  std::vector<std::size_t> order(s.support.size());
  for (std::size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::abs(s.coefficients(static_cast<Eigen::Index>(a))) >
           std::abs(s.coefficients(static_cast<Eigen::Index>(b)));
  });
  std::map<std::string, std::string> by_gate;  // gate -> its features, for `where`
  for (const std::size_t k : order)
    by_gate[library.features()[static_cast<std::size_t>(s.support[k])].gate] += "";
  const bool gated = by_gate.size() > 1;
  e.term.name = free_name();
  e.term.phase = gated ? "all" : by_gate.begin()->first;
  for (const std::size_t k : order) {
    const auto j = static_cast<std::size_t>(s.support[k]);
    const Feature& f = library.features()[j];
    const double standardised = s.coefficients(static_cast<Eigen::Index>(k));
    ExplainedFeature out{"c" + std::to_string(e.features.size() + 1), f.expression, f.gate,
                         standardised / d.scale[j], std::abs(standardised)};
    e.term.expression +=
        (e.term.expression.empty() ? "" : " + ") + term_part(out.parameter, f, gated);
    e.term.params[out.parameter] = out.coefficient;
    std::string& list = by_gate[f.gate];
    list += (list.empty() ? "" : ", ") + f.expression;
    e.features.push_back(std::move(out));
  }
  for (const auto& [gate, list] : by_gate)
    e.where += (e.where.empty() ? "" : "; ") + gate + ": " + list;
  double n = 0.0;
  for (const GramStats& g : d.groups) n += g.n;
  e.predicted_cv_rmse_N = std::sqrt(s.cv_sse / std::max(n, 1.0));
  e.predicted_gain_pct = gain_pct(std::sqrt(path.empty_sse()), std::sqrt(s.cv_sse));
  std::vector<double> before(runs_.size(), 0.0), after(runs_.size(), 0.0);
  const std::vector<double> empty = path.group_empty_sse();
  for (std::size_t g = 0; g < d.groups.size(); ++g)
    before[g / d.group_per_run] += empty[g], after[g / d.group_per_run] += s.group_cv_sse[g];
  e.runs_improved = fraction_improved(before, after);
}

void ResidualExplainer::validate(Explanation& e) const {
  ForceModel model = *model_;
  model.candidate_terms.push_back(e.term);
  const EffectCatalogue catalogue(model, runs_);
  std::vector<std::string> effects = options_.with;
  effects.push_back("user:" + e.term.name);
  const ModelFamily family(model, catalogue, effects);
  const CvResult cv = family.cross_validate(runs_);
  e.validated = true;
  e.after_cv_rmse_N = cv.rmse_N;
  e.after_gain_pct = gain_pct(base_cv_->rmse_N, cv.rmse_N);
  e.after_runs_improved = fraction_improved(base_cv_->run_sse, cv.run_sse);
  for (const UserTerm& u : family.user_terms(cv.full.params)) {
    if (u.name == e.term.name) e.fitted = u;
  }
}

std::string ResidualExplainer::free_name() const {
  auto taken = [&](const std::string& name) {
    for (const auto* terms : {&model_->user_terms, &model_->candidate_terms}) {
      for (const UserTerm& u : *terms) {
        if (u.name == name) return true;
      }
    }
    return false;
  };
  std::string name = options_.term_name;
  for (int k = 2; taken(name); ++k) name = options_.term_name + "_" + std::to_string(k);
  return name;
}

Explanation ResidualExplainer::explain() const {
  Explanation e;
  e.base_effects = base_->effect_names();
  e.baseline_cv_rmse_N = base_cv_->rmse_N;
  e.noise_floor_N = noise_floor(runs_);
  const std::vector<Covariate> covariates = this->covariates();
  const bool holds = std::any_of(runs_.begin(), runs_.end(), [](const PreparedRun* r) {
    return r->seg.hold_end > r->seg.hold_begin;
  });
  const FeatureLibrary library(covariates, holds);
  e.library_size = library.features().size();
  std::vector<RunRows> rows;
  for (std::size_t r = 0; r < runs_.size(); ++r) rows.push_back(sample_run(r, covariates));
  const Design d = design(library, rows);
  const LassoPath path(d.groups, d.fold_of, options_.max_features);
  double n = 0.0;
  for (const GramStats& g : d.groups) n += g.n;
  for (const PathStep& s : path.steps()) {
    if (e.path.empty() || e.path.back().first != s.support.size())
      e.path.emplace_back(s.support.size(), std::sqrt(s.cv_sse / std::max(n, 1.0)));
    e.path.back().second = std::min(e.path.back().second, std::sqrt(s.cv_sse / std::max(n, 1.0)));
  }
  const int step = path.choose();
  if (step < 0) {
    e.summary = "no combination of the " + std::to_string(e.library_size) +
                " candidate features lowers the held-out error: nothing to propose";
    return e;
  }
  describe(library, d, path,
           path.prune(path.steps()[static_cast<std::size_t>(step)], kMinFeatureShare), e);
  const std::string best = "user term " + e.term.expression + " (" + e.term.phase + ")";
  if (e.predicted_gain_pct < kMinGainPct || e.runs_improved < kMinRunsImproved) {
    e.summary = best + " would lower the held-out error by " +
                number("%.1f", e.predicted_gain_pct) + " % in " +
                number("%.0f", 100.0 * e.runs_improved) +
                " % of the runs: too little to propose (needs 5 % in 60 %)";
    return e;
  }
  if (!options_.validate) {
    e.proposed = true;
    e.summary = best + ": predicted to lower the CV error by " +
                number("%.1f", e.predicted_gain_pct) + " % (not fitted)";
    return e;
  }
  validate(e);
  e.proposed = e.after_gain_pct >= kMinGainPct && e.after_runs_improved >= kMinRunsImproved;
  e.summary = best +
              (e.proposed ? ": fitted with the model it" : ": fitted with the model it only") +
              " lowers the CV RMSE from " + number("%.4f", e.baseline_cv_rmse_N) + " to " +
              number("%.4f", e.after_cv_rmse_N) + " N (" + number("%.1f", e.after_gain_pct) +
              " %; noise floor " + number("%.4f", e.noise_floor_N) + " N)";
  return e;
}

Explanation explain(const ForceModel& model, const std::vector<RunData>& data,
                    const ExplainOptions& options) {
  std::vector<PreparedRun> prepared;
  prepared.reserve(data.size());
  for (const RunData& r : data) prepared.push_back(prepare_run(r));
  std::vector<const PreparedRun*> runs;
  runs.reserve(prepared.size());
  for (const PreparedRun& p : prepared) runs.push_back(&p);
  if (runs.empty()) throw std::invalid_argument("explain: no runs");
  const EffectCatalogue catalogue(model, runs);
  const ModelFamily base(model, catalogue, options.with);
  const CvResult cv = base.cross_validate(runs);
  Explanation e = ResidualExplainer(model, base, runs, cv, options).explain();
  for (const PreparedRun& p : prepared)
    e.warnings.insert(e.warnings.end(), p.warnings.begin(), p.warnings.end());
  return e;
}

}  // namespace rig::model::explainer
