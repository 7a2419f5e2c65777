#include "zoo_generator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <memory>

#include "rig/sim/active_effects.hpp"
#include "rig/sim/random_source.hpp"
#include "zoo_laws.hpp"

namespace rig::zoo {

using LawFactory =
    std::function<std::shared_ptr<const sim::ExtraForce>(const sim::RunSpec&, double size)>;

struct Recipe {
  DrawKind kind = DrawKind::kClean;
  std::string family = "clean", form = "no effect";
  std::vector<std::string> expected = {"none"};
  std::vector<sim::HiddenEffect> effects;  // at size 1
  std::vector<double> effect_scale;  // each effect's size relative to the draw's (empty: all 1)
  LawFactory law;                    // or nullptr
  double target = 0.0;               // wanted magnitude [x noise]
};

namespace {

constexpr double kNoise_N = 0.0015;  // the simulated load cell's white noise (SensorParams)
constexpr double kMaxSize = 25.0;    // never scale a form beyond this (its law would be absurd)
const char* const kCovariateKeys[] = {"post_mortem_h", "temperature_C", "blade_uses"};

double covariate_of(const sim::RunSpec& spec, const std::string& key) {
  if (key == "post_mortem_h") return spec.covariate_value;
  const auto at = spec.extra_meta.find(key);
  return at == spec.extra_meta.end() ? 0.0 : at->second;
}

// Centre and half range of each covariate's design, to put a random link on [-1, 1].
std::pair<double, double> covariate_scale(const std::string& key, int runs) {
  if (key == "post_mortem_h") return {2.0, 1.5};
  if (key == "temperature_C") return {22.0, 3.0};
  const double half = std::max(1.0, 0.5 * (runs - 1));
  return {half, half};
}

// A random link on z in [-1, 1]: curved, a soft step at a random threshold, or a bend. (Not
// linear: acting everywhere, a linear link is the lab's "linear, all phases" form exactly.)
std::function<double(double)> draw_link(sim::RandomSource& rng, std::string& words) {
  const int type = static_cast<int>(rng.uniform(0.0, 3.0));
  const double sign = rng.sign();
  if (type == 0) {
    words = "curved link";
    return [sign](double z) { return sign * (z + 0.5 * z * z); };
  }
  if (type == 1) {
    const double threshold = rng.uniform(-0.5, 0.5);
    words = "step link";
    return [sign, threshold](double z) { return sign * std::tanh((z - threshold) / 0.15); };
  }
  words = "bent link";
  return [sign](double z) { return sign * (z > 0.0 ? 1.5 * z : 0.3 * z); };
}

Window draw_window(sim::RandomSource& rng, std::initializer_list<Window> choices) {
  const auto index =
      static_cast<std::size_t>(rng.uniform(0.0, static_cast<double>(choices.size())));
  return *(choices.begin() + static_cast<std::ptrdiff_t>(std::min(index, choices.size() - 1)));
}

}  // namespace

std::string kind_name(DrawKind kind) {
  switch (kind) {
    case DrawKind::kClean:
      return "clean";
    case DrawKind::kCatalogueForm:
      return "catalogue family, simulator form";
    case DrawKind::kZooLaw:
      return "catalogue family, random law";
    case DrawKind::kOutOfCatalogue:
      return "out of catalogue";
    case DrawKind::kMixture:
      return "mixture";
  }
  return "?";
}

std::vector<sim::RunSpec> ZooGenerator::run_specs(std::uint64_t seed) const {
  sim::RandomSource rng(seed * 7919 + 17);
  const double iops[3] = {15.0, 16.5, 18.0};
  const double velocities[3] = {0.6, 1.4, 3.2};
  std::vector<int> order(static_cast<std::size_t>(o_.runs));
  for (int k = 0; k < o_.runs; ++k) order[static_cast<std::size_t>(k)] = k;
  for (int k = o_.runs - 1; k > 0; --k)
    std::swap(order[static_cast<std::size_t>(k)],
              order[static_cast<std::size_t>(rng.uniform(0.0, k + 0.999))]);
  std::vector<sim::RunSpec> specs;
  for (int k = 0; k < o_.runs; ++k) {
    sim::RunSpec s;
    s.iop_mmHg = std::clamp(iops[(k / 3) % 3] + rng.uniform(-0.3, 0.3), 15.0, 18.0);
    s.velocity_mm_s = std::clamp(velocities[k % 3] * std::exp(rng.uniform(-0.15, 0.15)), 0.5, 4.0);
    sim::apply_standard_protocol(s);
    s.covariate_value = rng.uniform(0.5, 3.5);  // post_mortem_h
    s.extra_meta["temperature_C"] = rng.uniform(19.0, 25.0);
    s.extra_meta["blade_uses"] =
        order[static_cast<std::size_t>(k)];  // the blade's cuts before this one
    s.seed = seed * 1000 + static_cast<std::uint64_t>(k);
    s.eye_id = "ZOO-" + std::to_string(seed) + "-" + std::to_string(k);
    specs.push_back(s);
  }
  return specs;
}

namespace {

sim::HiddenEffect draw_sim_effect(sim::RandomSource& rng, int kind) {
  sim::HiddenEffect e;
  e.kind = static_cast<sim::EffectKind>(kind);
  const auto forms = sim::effect_forms(e.kind);
  e.form = forms[std::min(forms.size() - 1, static_cast<std::size_t>(rng.uniform(
                                                0.0, static_cast<double>(forms.size()))))];
  if (e.kind == sim::EffectKind::kCovariate) e.covariate = "post_mortem_h";
  return e;
}

std::string verdict_of(const sim::HiddenEffect& e) {
  return e.kind == sim::EffectKind::kCovariate ? "covariate:" + e.covariate
                                               : sim::effect_name(e.kind);
}

int draw_family(sim::RandomSource& rng) {
  return static_cast<int>(rng.uniform(0.0, sim::kEffectKindCount - 1e-9));
}

void catalogue_form(Recipe& r, sim::RandomSource& rng) {
  r.kind = DrawKind::kCatalogueForm;
  r.effects = {draw_sim_effect(rng, draw_family(rng))};
  r.family = verdict_of(r.effects[0]);
  r.form = sim::effect_name(r.effects[0].kind) + ":" + r.effects[0].form;
  r.expected = {r.family};
}

void zoo_law(Recipe& r, sim::RandomSource& rng, int runs) {
  r.kind = DrawKind::kZooLaw;
  if (rng.uniform(0.0, 1.0) < 0.5) {
    const VelocityLaw law = VelocityLaw::draw(rng);
    const Window window = draw_window(rng, {Window::kAllInsert, Window::kCutInsert});
    r.family = "rate_dependence";
    r.form = "random law in velocity, " + window_name(window);
    r.law = [law, window](const sim::RunSpec&, double size) {
      return std::make_shared<VelocityScaledLaw>(law, window, 0.1 * size);
    };
  } else {
    const std::string key = kCovariateKeys[std::min(2, static_cast<int>(rng.uniform(0.0, 3.0)))];
    std::string words;
    const auto link = draw_link(rng, words);
    const Window window =
        draw_window(rng, {Window::kAll, Window::kCutInsert, Window::kPrecutInsert});
    // Named copies: a lambda may not capture a structured binding under clang (C++20 allows it).
    const auto scale = covariate_scale(key, runs);
    const double centre = scale.first, half = scale.second;
    r.family = "covariate:" + key;
    r.form = words + " of " + key + ", " + window_name(window);
    r.law = [=](const sim::RunSpec& spec, double size) {
      const double z = std::clamp((covariate_of(spec, key) - centre) / half, -1.5, 1.5);
      return std::make_shared<RunFactorLaw>(std::max(kMostWeakening, 0.1 * size * link(z)), window);
    };
  }
  r.expected = {r.family};
}

void out_of_catalogue(Recipe& r, sim::RandomSource& rng) {
  r.kind = DrawKind::kOutOfCatalogue;
  r.family = "out_of_catalogue";
  r.expected = {"unexplained"};
  if (rng.uniform(0.0, 1.0) < 0.25) {
    const double period = rng.uniform(0.4, 1.5), decay = rng.uniform(0.5, 2.0);
    r.form = "damped ringing in every hold";
    r.law = [=](const sim::RunSpec&, double size) {
      return std::make_shared<HoldRingingLaw>(0.003 * size, period, decay);
    };
    return;
  }
  const Window window =
      draw_window(rng, {Window::kPrecutInsert, Window::kCutInsert, Window::kRetraction});
  const BumpSum bumps = window == Window::kCutInsert      ? BumpSum::draw(rng, 0.3, 6.0)
                        : window == Window::kPrecutInsert ? BumpSum::draw(rng, 0.3, 3.3)
                                                          : BumpSum::draw(rng, 1.0, 11.0);
  r.form = "random bumps in depth, " + window_name(window);
  r.law = [=](const sim::RunSpec&, double size) {
    return std::make_shared<DepthBumpsLaw>(bumps, window, 0.003 * size);
  };
}

void mixture(Recipe& r, sim::RandomSource& rng) {
  r.kind = DrawKind::kMixture;
  const int first = draw_family(rng);
  int second = static_cast<int>(rng.uniform(0.0, sim::kEffectKindCount - 1 - 1e-9));
  if (second >= first) ++second;
  r.effects = {draw_sim_effect(rng, first), draw_sim_effect(rng, second)};
  r.expected = {verdict_of(r.effects[0]), verdict_of(r.effects[1])};
  r.family = r.expected[0] + "+" + r.expected[1];
  r.form = sim::effect_name(r.effects[0].kind) + ":" + r.effects[0].form + " + " +
           sim::effect_name(r.effects[1].kind) + ":" + r.effects[1].form;
  r.target = std::max(
      r.target,
      3.0);  // both must be findable: each is scaled to this on its own (ZooGenerator::draw)
}

// Effect k of a recipe at the draw's size (times its own scale, in a mixture).
sim::HiddenEffect sized_effect(const Recipe& r, std::size_t k, double size) {
  sim::HiddenEffect e = r.effects[k];
  e.size = size * (k < r.effect_scale.size() ? r.effect_scale[k] : 1.0);
  return e;
}

}  // namespace

Recipe ZooGenerator::recipe(std::uint64_t seed) const {
  sim::RandomSource rng(seed * 104729 + 3);
  Recipe r;
  r.target =
      o_.min_magnitude * std::pow(o_.max_magnitude / o_.min_magnitude, rng.uniform(0.0, 1.0));
  const double total = o_.clean_share + o_.catalogue_share + o_.zoo_law_share +
                       o_.out_of_catalogue_share + o_.mixture_share;
  double pick = rng.uniform(0.0, total);
  if ((pick -= o_.clean_share) < 0.0) return r;
  if ((pick -= o_.catalogue_share) < 0.0) {
    catalogue_form(r, rng);
  } else if ((pick -= o_.zoo_law_share) < 0.0) {
    zoo_law(r, rng, o_.runs);
  } else if (pick < o_.out_of_catalogue_share) {
    out_of_catalogue(r, rng);
  } else {
    mixture(r, rng);
  }
  return r;
}

std::vector<model::RunData> ZooGenerator::simulate(const Recipe& r,
                                                   const std::vector<sim::RunSpec>& specs,
                                                   double size, std::size_t count,
                                                   double eye_variability) const {
  sim::GeneratorOptions g;
  g.physics.tissue.eye_variability = eye_variability;
  for (std::size_t k = 0; k < r.effects.size(); ++k) g.effects.push_back(sized_effect(r, k, size));
  if (r.law) {
    const LawFactory law = r.law;
    g.extra_force = [law, size](const sim::RunSpec& spec) { return law(spec, size); };
  }
  std::vector<model::RunData> runs;
  for (std::size_t k = 0; k < count && k < specs.size(); ++k) {
    // Pilot runs are spread over the design (its diagonal), not three of one IOP.
    const std::size_t at = count < specs.size() ? (k * 4) % specs.size() : k;
    runs.push_back(sim::generate_run(g, specs[at]));
  }
  return runs;
}

double ZooGenerator::pilot_magnitude(const Recipe& r, const std::vector<sim::RunSpec>& specs,
                                     double size, std::size_t runs) const {
  Recipe clean;
  return effect_rms_ratio(simulate(r, specs, size, runs), simulate(clean, specs, size, runs),
                          kNoise_N);
}

double ZooGenerator::true_floor_N(const std::vector<sim::RunSpec>& specs) const {
  // The same eyes' noise and tearing with identical eyes: what differs is the eye variation.
  Recipe clean;
  const double eye_N =
      kNoise_N * effect_rms_ratio(simulate(clean, specs, 1.0, kPilotRuns),
                                  simulate(clean, specs, 1.0, kPilotRuns, 0.0), kNoise_N);
  return std::sqrt(kNoise_N * kNoise_N + eye_N * eye_N);
}

// A mixture's effects each at the draw's magnitude on their own: scaled together, one form's
// natural size could leave the other below the floor (200041: a ripple of 3.4 mN amplitude
// beside friction, under half the floor on its own), and no lab could name what the data do
// not show. Returns the
// magnitude each has alone [x the true floor].
std::vector<double> ZooGenerator::calibrate_components(Recipe& r,
                                                       const std::vector<sim::RunSpec>& specs,
                                                       double floor_in_noise) const {
  std::vector<double> alone;
  r.effect_scale.clear();
  for (const sim::HiddenEffect& e : r.effects) {
    Recipe one;
    one.kind = DrawKind::kCatalogueForm;
    one.effects = {e};
    // Measured on every run of the draw, not three pilots, and again at the size found: some
    // forms are not linear in their size (a relaxation spectrum's strength saturates; seed
    // 770102 came out at 2.0x where one linear step from three pilots said 3.0x). A form that
    // cannot reach the target is labelled with what it reaches.
    double scale = 1.0, magnitude = pilot_magnitude(one, specs, scale, specs.size());  // x noise
    for (int pass = 0; pass < 3 && magnitude > 1e-9; ++pass) {
      scale = std::min(kMaxSize, scale * r.target * floor_in_noise / magnitude);
      magnitude = pilot_magnitude(one, specs, scale, specs.size());
    }
    r.effect_scale.push_back(scale);
    alone.push_back(magnitude / floor_in_noise);
  }
  return alone;
}

ZooDraw ZooGenerator::draw(std::uint64_t seed) const {
  Recipe r = recipe(seed);
  const std::vector<sim::RunSpec> specs = run_specs(seed);
  ZooDraw d;
  d.seed = seed;
  d.kind = r.kind;
  d.family = r.family;
  d.form = r.form;
  d.expected = r.expected;
  d.floor_N = true_floor_N(specs);
  const double floor_in_noise = d.floor_N / kNoise_N;
  double size = 1.0;
  if (r.kind == DrawKind::kMixture) {
    d.component_magnitudes = calibrate_components(r, specs, floor_in_noise);
    d.magnitude_noise = pilot_magnitude(r, specs, 1.0, specs.size());
    d.magnitude = d.magnitude_noise / floor_in_noise;
  } else if (r.kind != DrawKind::kClean) {
    // The effects are close to linear in their size: one pilot at size 1 sets the scale.
    const double at_one = pilot_magnitude(r, specs, 1.0);  // x noise
    size = at_one > 1e-9 ? std::min(kMaxSize, r.target * floor_in_noise / at_one) : 1.0;
    d.magnitude_noise = at_one * size;
    d.magnitude = d.magnitude_noise / floor_in_noise;
  }
  for (std::size_t k = 0; k < r.effects.size(); ++k) d.hidden.push_back(sized_effect(r, k, size));
  try {
    d.runs = simulate(r, specs, size, specs.size());
  } catch (const sim::RunFaulted& e) {  // say what the draw hid, and how large
    char size_text[48];
    std::snprintf(size_text, sizeof size_text, " at %.1fx the floor: ", d.magnitude);
    throw sim::RunFaulted(d.family + ", " + d.form + size_text + e.what());
  }
  return d;
}

double effect_rms_ratio(const std::vector<model::RunData>& with,
                        const std::vector<model::RunData>& without, double noise_N) {
  double sum = 0.0;
  double n = 0.0;
  for (std::size_t r = 0; r < with.size() && r < without.size(); ++r) {
    const std::size_t samples = std::min(with[r].size(), without[r].size());
    for (std::size_t i = 0; i < samples; ++i) {
      if (without[r].x_mm[i] <= 0.0) continue;
      const double e = with[r].force_N[i] - without[r].force_N[i];
      sum += e * e;
      n += 1.0;
    }
  }
  return n > 0.0 ? std::sqrt(sum / n) / noise_N : 0.0;
}

}  // namespace rig::zoo
