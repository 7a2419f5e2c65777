#include "effect_catalogue.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include "predictor.hpp"

#include "effects/covariate_scaling.hpp"
#include "effects/family_term.hpp"
#include "effects/form_selection.hpp"
#include "effects/iop_stiffness.hpp"
#include "effects/mains_interference.hpp"
#include "effects/rate_dependence.hpp"
#include "effects/rig_compliance.hpp"
#include "effects/sensor_drift.hpp"
#include "effects/shaft_friction.hpp"
#include "effects/spatial_ripple.hpp"
#include "effects/stick_slip.hpp"
#include "effects/stress_relaxation.hpp"
#include "effects/user_expression.hpp"

namespace rig::model {
namespace {

// Keys that are bookkeeping or inputs the model already uses: never covariates.
bool excluded_key(const std::string& key) {
  static const std::set<std::string> kExcluded = {"iop_mmHg",
                                                  "velocity_mm_s",
                                                  "depth_mm",
                                                  "hold_s",
                                                  "run_id",
                                                  "original_run_id",
                                                  "config_hash",
                                                  "software_version",
                                                  "started_at",
                                                  "outcome",
                                                  "reason",
                                                  "source",
                                                  "rate_hz",
                                                  "surface_mm",
                                                  "iop_meas_mmHg",
                                                  "velocity_meas_mm_s",
                                                  "displacement_scale"};
  if (kExcluded.count(key) != 0U) return true;
  if (key.size() > 3 && key.compare(key.size() - 3, 3, "_id") == 0) return true;
  return key.find("_cmd_") != std::string::npos;  // the rig's own commands (motor_cmd_V)
}

std::vector<std::string> candidate_keys(const std::vector<const PreparedRun*>& runs) {
  std::set<std::string> keys;
  for (const PreparedRun* r : runs) {
    for (const auto& [k, v] : r->data->meta) {
      if (r->data->number(k)) keys.insert(k);
    }
    for (const auto& c : r->data->channels) keys.insert(c.name);
    for (const auto& [k, v] : r->derived) keys.insert(k);  // run_order
  }
  std::vector<std::string> out;
  for (const auto& k : keys) {
    const bool everywhere = std::all_of(runs.begin(), runs.end(), [&](const PreparedRun* r) {
      return r->covariate(k, 0).has_value();
    });
    if (everywhere && !excluded_key(k)) out.push_back(k);
  }
  return out;
}

effects::CovariateRange covariate_stats(const std::string& key,
                                        const std::vector<const PreparedRun*>& runs) {
  effects::CovariateRange out;
  out.low = std::numeric_limits<double>::infinity();
  out.high = -out.low;
  std::vector<double> values;
  for (const PreparedRun* r : runs) {
    double sum = 0.0;
    for (const std::size_t i : r->analysed) {
      const double v = r->covariate(key, i).value_or(0.0);
      sum += v;
      out.low = std::min(out.low, v);
      out.high = std::max(out.high, v);
    }
    values.push_back(r->analysed.empty() ? 0.0 : sum / static_cast<double>(r->analysed.size()));
  }
  for (const double v : values) out.mean += v;
  out.mean /= static_cast<double>(std::max<std::size_t>(values.size(), 1));
  double var = 0.0;
  for (const double v : values) var += (v - out.mean) * (v - out.mean);
  out.spread = std::sqrt(var / static_cast<double>(std::max<std::size_t>(values.size(), 1)));
  if (!(out.low <= out.high)) {  // no samples, or no number among them: no range to hold to
    out.low = -std::numeric_limits<double>::infinity();
    out.high = std::numeric_limits<double>::infinity();
  } else if (values.size() > 1 && std::all_of(values.begin(), values.end(), [](double v) {
               return std::abs(v - std::round(v)) < 1e-9;
             })) {  // a count (blade uses, run order): one run's spacing past the edges
    out.reach = (out.high - out.low) / static_cast<double>(values.size() - 1);
  }
  return out;
}

}  // namespace

const std::vector<std::string>& EffectCatalogue::builtin_names() {
  static const std::vector<std::string> kNames = {
      "rate_dependence", "iop_stiffness",      "shaft_friction", "rig_compliance",   "sensor_drift",
      "spatial_ripple",  "mains_interference", "stick_slip",     "stress_relaxation"};
  return kNames;
}

EffectCatalogue::EffectCatalogue(const ForceModel& model,
                                 const std::vector<const PreparedRun*>& runs)
    : model_(&model), runs_(runs) {
  covariates_ = candidate_keys(runs);
  for (const auto& key : covariates_) covariate_stats_.push_back(covariate_stats(key, runs));
}

std::shared_ptr<EffectCatalogue> EffectCatalogue::with_settings_on(
    const std::vector<const PreparedRun*>& subset) const {
  auto out = std::make_shared<EffectCatalogue>(*model_, subset);
  out->with_ = with_;
  out->select_forms_ = select_forms_;
  return out;
}

std::shared_ptr<const EffectCatalogue> EffectCatalogue::on_runs(
    const std::vector<const PreparedRun*>& subset) const {
  std::vector<bool> member(runs_.size(), false);
  std::size_t next = 0;  // the subset must list our runs in our order to share their choices
  for (const PreparedRun* run : subset) {
    const auto at = std::find(runs_.begin() + static_cast<std::ptrdiff_t>(next), runs_.end(), run);
    if (at == runs_.end())
      return with_settings_on(subset);  // not our runs, or reordered: nothing to share
    next = static_cast<std::size_t>(at - runs_.begin()) + 1;
    member[next - 1] = true;
  }
  const std::lock_guard<std::mutex> lock(cache_->mutex);
  auto& cached = cache_->on_subsets[member];
  if (!cached)
    cached = with_settings_on(subset);  // cheap: the forms are chosen when first asked for
  return cached;
}

std::vector<std::string> EffectCatalogue::candidates() const {
  std::vector<std::string> out = builtin_names();
  for (const auto& key : covariates_) out.push_back("covariate:" + key);
  for (const UserTerm& term : model_->candidate_terms) out.push_back("user:" + term.name);
  return out;
}

std::unique_ptr<EffectTerm> EffectCatalogue::make_in_form(const std::string& name, int form) const {
  using namespace effects;
  auto in = [form](int fallback) { return form < 0 ? fallback : form; };
  if (name == "rate_dependence")
    return std::make_unique<RateDependence>(model_->reference_velocity_mm_s,
                                            in(RateDependence::kLogQuadratic));
  if (name == "iop_stiffness")
    return std::make_unique<IopStiffness>(in(IopStiffness::kExponentialQuadratic));
  if (name == "shaft_friction")
    return std::make_unique<ShaftFriction>(in(ShaftFriction::kSaturating));
  if (name == "rig_compliance")
    return std::make_unique<RigCompliance>(in(RigCompliance::kPolynomial));
  if (name == "sensor_drift") return std::make_unique<SensorDrift>(in(SensorDrift::kPolynomial));
  if (name == "spatial_ripple")
    return std::make_unique<SpatialRipple>(in(SpatialRipple::kThreeHarmonics));
  if (name == "mains_interference")
    return std::make_unique<MainsInterference>(in(MainsInterference::kHarmonics));
  if (name == "stick_slip") return std::make_unique<StickSlip>(in(StickSlip::kThreeHarmonics));
  if (name == "stress_relaxation")
    return std::make_unique<StressRelaxation>(in(StressRelaxation::kStretched));
  if (name.rfind("covariate:", 0) == 0) {
    const std::string key = name.substr(10);
    const auto at = std::find(covariates_.begin(), covariates_.end(), key);
    if (at == covariates_.end())
      throw std::invalid_argument("effect '" + name + "': no numeric covariate '" + key +
                                  "' in every run");
    CovariateRange range = covariate_stats_[static_cast<std::size_t>(at - covariates_.begin())];
    if (range.spread <= 0.0) range.spread = 1.0;
    return std::make_unique<CovariateScaling>(key, range, in(CovariateScaling::kPerPhase));
  }
  if (name.rfind("user:", 0) == 0) {
    for (const auto* terms : {&model_->user_terms, &model_->candidate_terms}) {
      for (const UserTerm& term : *terms) {
        if ("user:" + term.name == name) return std::make_unique<UserExpression>(term);
      }
    }
  }
  std::string known;
  for (const auto& n : candidates()) known += (known.empty() ? "" : ", ") + n;
  for (const UserTerm& term : model_->user_terms) known += ", user:" + term.name;
  if (name.rfind("user:", 0) == 0)
    known += "; user terms come from the model file's [terms] or --terms FILE";
  throw std::invalid_argument("unknown effect '" + name + "' (known: " + known + ")");
}

std::unique_ptr<EffectTerm> EffectCatalogue::make(const std::string& name) const {
  auto term = make_in_form(name, -1);
  std::string why_not;
  if (!select_forms_ || term->forms().size() < 2 || runs_.empty() ||
      !term->applicable(runs_, why_not))
    return term;
  return selected(name);
}

std::unique_ptr<EffectTerm> EffectCatalogue::make_form(const std::string& name,
                                                       const std::string& form) const {
  const auto forms = make_in_form(name, -1)->forms();
  const int index = effects::form_named(forms, form);
  if (index < 0) {
    std::string known;
    for (const auto& f : forms) known += (known.empty() ? "" : ", ") + f;
    throw std::invalid_argument("effect '" + name + "': unknown form '" + form +
                                "' (known: " + (known.empty() ? "none" : known) + ")");
  }
  return make_in_form(name, index);
}

std::unique_ptr<EffectTerm> EffectCatalogue::selected(const std::string& name) const {
  auto with_note = [&](int form, const std::string& note) {
    auto term = make_in_form(name, form);
    if (auto* family = dynamic_cast<effects::FamilyTerm*>(term.get()))
      family->set_selection_note(note);
    return term;
  };
  {
    const std::lock_guard<std::mutex> lock(cache_->mutex);
    const auto it = cache_->chosen.find(name);
    if (it != cache_->chosen.end()) return with_note(it->second.first, it->second.second);
  }
  // Selected outside the lock: the other threads select their own families meanwhile.
  std::vector<SavedEffect> base = saved_effects(*model_, *this);
  std::vector<std::unique_ptr<EffectTerm>> with_terms;
  effects::FormSelectionInput in;
  in.model = model_;
  for (const SavedEffect& saved : base)
    in.base_terms.push_back(saved.term.get()), in.base_params.push_back(saved.params);
  for (const std::string& w : with_) {
    if (w == name) continue;
    // The accepted effects in the form already chosen for them, else their default form:
    // selecting them here (make) would recurse when two or more are accepted.
    int form = -1;
    {
      const std::lock_guard<std::mutex> lock(cache_->mutex);
      const auto it = cache_->chosen.find(w);
      if (it != cache_->chosen.end()) form = it->second.first;
    }
    with_terms.push_back(make_in_form(w, form));
    in.base_terms.push_back(with_terms.back().get());
    in.base_params.push_back(
        Predictor(*model_, {with_terms.back().get()}).initial_params().shared.front());
  }
  in.runs = runs_;
  in.forms = static_cast<int>(make_in_form(name, -1)->forms().size());
  in.make_form = [&](int form) { return make_in_form(name, form); };
  // The shared baseline holds every accepted effect; an accepted effect's own form is chosen
  // over a baseline without it, whose terms differ: that one is fitted for it alone.
  const bool accepted = std::find(with_.begin(), with_.end(), name) != with_.end();
  std::shared_ptr<const effects::SelectionBaseline> baseline;
  if (accepted) {
    baseline =
        std::make_shared<const effects::SelectionBaseline>(effects::fit_selection_baseline(in));
  } else {
    std::call_once(cache_->baseline_once, [&] {
      cache_->baseline =
          std::make_shared<const effects::SelectionBaseline>(effects::fit_selection_baseline(in));
    });
    baseline = cache_->baseline;
  }
  const effects::FormChoice choice = effects::select_form(in, *baseline);
  const std::lock_guard<std::mutex> lock(cache_->mutex);
  cache_->chosen.emplace(name, std::make_pair(choice.form, choice.note));
  return with_note(choice.form, choice.note);
}

std::unique_ptr<EffectTerm> EffectCatalogue::make_saved(const EffectSetting& setting) const {
  const auto mean = setting.params.find("mean");
  const auto spread = setting.params.find("spread");
  const auto low = setting.params.find("low");
  const auto high = setting.params.find("high");
  const auto reach = setting.params.find("reach");
  const bool saved_covariate = setting.name.rfind("covariate:", 0) == 0 &&
                               mean != setting.params.end() && spread != setting.params.end();
  auto build = [&](int form) -> std::unique_ptr<EffectTerm> {
    // A covariate term keeps the centre and scale it was fitted with.
    if (saved_covariate) {
      effects::CovariateRange range;
      range.mean = mean->second;
      range.spread = spread->second;
      if (low != setting.params.end())
        range.low = low->second;  // files before 2026-11-28 have none
      if (high != setting.params.end()) range.high = high->second;
      if (reach != setting.params.end()) range.reach = reach->second;  // since 2026-12-07
      // From a file a person may have edited: a range the term cannot hold to is an error
      // naming the effect, not a division by zero or an inverted clamp.
      if (!(range.spread > 0.0) || !(range.low <= range.high) || !(range.reach >= 0.0)) {
        throw std::invalid_argument(
            "effect '" + setting.name + "': needs spread > 0, low <= high and reach >= 0 (spread " +
            std::to_string(range.spread) + ", low " + std::to_string(range.low) + ", high " +
            std::to_string(range.high) + ", reach " + std::to_string(range.reach) + ")");
      }
      return std::make_unique<effects::CovariateScaling>(
          setting.name.substr(10), range, form < 0 ? effects::CovariateScaling::kPerPhase : form);
    }
    return make_in_form(setting.name, form);
  };
  auto term = build(-1);
  int best = -1;
  std::size_t best_names = 0;
  for (int f = 0; f < static_cast<int>(term->forms().size()); ++f) {
    const auto specs = build(f)->shared_params();
    const bool all_present = std::all_of(specs.begin(), specs.end(), [&](const ParamSpec& s) {
      return setting.params.count(s.name) != 0U;
    });
    if (all_present && (best < 0 || specs.size() > best_names)) best = f, best_names = specs.size();
  }
  return best < 0 ? std::move(term) : build(best);
}

std::vector<SavedEffect> saved_effects(const ForceModel& model, const EffectCatalogue& catalogue) {
  std::vector<SavedEffect> out;
  for (const EffectSetting& setting : model.effects) {
    SavedEffect saved;
    saved.term = catalogue.make_saved(setting);
    for (const ParamSpec& spec : saved.term->shared_params()) {
      const auto it = setting.params.find(spec.name);
      saved.params.push_back(it != setting.params.end() ? it->second : spec.initial);
    }
    out.push_back(std::move(saved));
  }
  for (const UserTerm& term : model.user_terms) {
    SavedEffect saved{std::make_unique<effects::UserExpression>(term), {}};
    for (const ParamSpec& spec : saved.term->shared_params()) saved.params.push_back(spec.initial);
    out.push_back(std::move(saved));
  }
  return out;
}

}  // namespace rig::model
