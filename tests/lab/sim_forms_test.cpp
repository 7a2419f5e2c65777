// The simulator is not the lab's mirror: no simulated effect form is a special case of any
// of the lab's forms for its family. Each simulated law is compared, as a function of what it
// depends on (speed, pressure, time in a hold, load), with every form of the lab's family,
// the lab's parameters searched within their bounds; the best fit must leave more than
// kLeftOver of the simulated effect unexplained. (Until 2026-11-28 the tests compared each
// simulated form with one lab form per family, and nine simulated forms were exact special
// cases of lab forms added later: the linear rate law, the linear and saturating IOP laws, the
// two-term Prony and power-law relaxations, the stiffening mount, Coulomb + viscous friction,
// the sensor's warm-up and the tearing period's power law in the speed.)
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "effects/iop_stiffness.hpp"
#include "effects/rate_dependence.hpp"
#include "effects/rig_compliance.hpp"
#include "effects/stick_slip.hpp"
#include "effects/stress_relaxation.hpp"
#include "rig/sim/effect_forms.hpp"
#include "rig/sim/hidden_effect.hpp"

namespace rig::sim {
namespace {

// An exact special case leaves nothing: the nine found on 2026-11-28 left under 0.00005 of
// their effect to this search. A different law leaves more than a thousandth; the closest
// (over a 3 s hold, any smooth relaxation is nearly two exponentials) leave 0.0017-0.005, and
// docs/sim.md quotes each form's closest lab form.
constexpr double kLeftOver = 0.001;

EffectSlot slot(EffectKind kind, const std::string& form) {
  const auto forms = effect_forms(kind);
  EffectSlot s;
  s.on = true;
  s.form = static_cast<int>(std::find(forms.begin(), forms.end(), form) - forms.begin());
  EXPECT_LT(s.form, static_cast<int>(forms.size())) << form;
  return s;
}

std::vector<double> grid(double from, double to, int n) {
  std::vector<double> out;
  for (int i = 0; i < n; ++i) out.push_back(from + (to - from) * i / (n - 1));
  return out;
}

struct Bounds {
  std::vector<double> lower, upper;
};

Bounds bounds_of(const std::vector<model::ParamSpec>& specs, int count) {
  Bounds b;
  for (int k = 0; k < count; ++k) {
    b.lower.push_back(specs[static_cast<std::size_t>(k)].lower);
    b.upper.push_back(specs[static_cast<std::size_t>(k)].upper);
  }
  return b;
}

// RMS of (target - law(p)) over the grid relative to the RMS of the target's change from its
// value where the effect is nil (`nil`: 1 for factors, 0 for shifts and fractions).
double misfit(const std::vector<double>& xs, const std::function<double(double)>& target,
              double nil, const std::function<double(double, const double*)>& law,
              const double* p) {
  double err = 0.0, size = 0.0;
  for (const double x : xs) {
    const double t = target(x);
    err += (t - law(x, p)) * (t - law(x, p));
    size += (t - nil) * (t - nil);
  }
  return std::sqrt(err / std::max(size, 1e-300));
}

// Search coordinates: a parameter bounded away from zero (a time, a speed, a load) on a log
// scale, where its valleys are round; the others as they are.
struct Coordinates {
  const Bounds* b;
  bool logarithmic(std::size_t k) const { return b->lower[k] > 0.0; }
  double lo(std::size_t k) const { return logarithmic(k) ? std::log(b->lower[k]) : b->lower[k]; }
  double hi(std::size_t k) const { return logarithmic(k) ? std::log(b->upper[k]) : b->upper[k]; }
  std::vector<double> params(const std::vector<double>& u) const {
    std::vector<double> p(u.size());
    for (std::size_t k = 0; k < u.size(); ++k) {
      const double c = std::clamp(u[k], lo(k), hi(k));
      p[k] = logarithmic(k) ? std::exp(c) : c;
    }
    return p;
  }
};

// Nelder-Mead from u0 (simplex edges a tenth of each range) [the misfit it reached].
double nelder_mead(const std::function<double(const std::vector<double>&)>& f, const Coordinates& c,
                   std::vector<double> u0) {
  const std::size_t n = u0.size();
  std::vector<std::vector<double>> x(n + 1, u0);
  for (std::size_t k = 0; k < n; ++k) x[k + 1][k] += 0.1 * (c.hi(k) - c.lo(k));
  std::vector<double> fx(n + 1);
  for (std::size_t i = 0; i <= n; ++i) fx[i] = f(x[i]);
  for (int iteration = 0; iteration < 4000; ++iteration) {
    std::vector<std::size_t> order(n + 1);
    for (std::size_t i = 0; i <= n; ++i) order[i] = i;
    std::sort(order.begin(), order.end(),
              [&](std::size_t a, std::size_t b) { return fx[a] < fx[b]; });
    const std::size_t best = order.front(), worst = order.back(), second = order[n - 1];
    if (fx[worst] - fx[best] < 1e-12) break;
    std::vector<double> centre(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i) {
      if (i == worst) continue;
      for (std::size_t k = 0; k < n; ++k) centre[k] += x[i][k] / static_cast<double>(n);
    }
    const auto along = [&](double t) {
      std::vector<double> y(n);
      for (std::size_t k = 0; k < n; ++k) y[k] = centre[k] + t * (x[worst][k] - centre[k]);
      return y;
    };
    const std::vector<double> reflected = along(-1.0);
    const double fr = f(reflected);
    if (fr < fx[best]) {
      const std::vector<double> expanded = along(-2.0);
      const double fe = f(expanded);
      if (fe < fr)
        x[worst] = expanded, fx[worst] = fe;
      else
        x[worst] = reflected, fx[worst] = fr;
    } else if (fr < fx[second]) {
      x[worst] = reflected, fx[worst] = fr;
    } else {
      const std::vector<double> contracted = along(0.5);
      const double fc = f(contracted);
      if (fc < fx[worst]) {
        x[worst] = contracted, fx[worst] = fc;
      } else {  // shrink towards the best
        for (std::size_t i = 0; i <= n; ++i) {
          if (i == best) continue;
          for (std::size_t k = 0; k < n; ++k) x[i][k] = x[best][k] + 0.5 * (x[i][k] - x[best][k]);
          fx[i] = f(x[i]);
        }
      }
    }
  }
  return *std::min_element(fx.begin(), fx.end());
}

// The least misfit within the bounds: 4000 random starts, Nelder-Mead from the best twenty.
double best_misfit(const std::vector<double>& xs, const std::function<double(double)>& target,
                   double nil, const std::function<double(double, const double*)>& law,
                   const Bounds& b) {
  const Coordinates c{&b};
  const auto f = [&](const std::vector<double>& u) {
    return misfit(xs, target, nil, law, c.params(u).data());
  };
  std::mt19937 rng(7);
  std::vector<std::pair<double, std::vector<double>>> starts;
  for (int start = 0; start < 4000; ++start) {
    std::vector<double> u(b.lower.size());
    for (std::size_t k = 0; k < u.size(); ++k)
      u[k] = std::uniform_real_distribution<double>(c.lo(k), c.hi(k))(rng);
    starts.emplace_back(f(u), u);
  }
  std::partial_sort(starts.begin(), starts.begin() + 20, starts.end(),
                    [](const auto& a, const auto& z) { return a.first < z.first; });
  double best = INFINITY;
  for (int k = 0; k < 20; ++k)
    best = std::min(best, nelder_mead(f, c, starts[static_cast<std::size_t>(k)].second));
  return best;
}

// Every form of the lab's family (made by `make`), its first parameters (all but the last
// `not_in_law`: where a law acts, not its shape) searched, against the simulated law.
template <typename Term>
void expect_no_lab_form_fits(
    const std::string& family, const std::string& sim_form, const std::vector<double>& xs,
    const std::function<double(double)>& target, double nil,
    const std::function<double(const Term&, double, const double*)>& lab_value,
    const std::function<Term(int)>& make, int not_in_law = 0) {
  const Term probe = make(0);
  for (int form = 0; form < static_cast<int>(probe.forms().size()); ++form) {
    const Term term = make(form);
    const auto specs = term.shared_params();
    const int used = static_cast<int>(specs.size()) - not_in_law;
    if (used <= 0) continue;
    const double left = best_misfit(
        xs, target, nil, [&](double x, const double* p) { return lab_value(term, x, p); },
        bounds_of(specs, used));
    std::printf("%s:%-14s against the lab's %-24s %.4f of the effect left over\n", family.c_str(),
                sim_form.c_str(), term.form().c_str(), left);
    EXPECT_GT(left, kLeftOver) << family << ":" << sim_form << " is the lab's " << term.form();
  }
}

using model::effects::IopStiffness;
using model::effects::RateDependence;
using model::effects::RigCompliance;
using model::effects::StressRelaxation;

TEST(SimulatedForms, NoRateLawIsOneOfTheLabsRateLaws) {
  for (const std::string& form : effect_forms(EffectKind::kRateDependence)) {
    const EffectSlot s = slot(EffectKind::kRateDependence, form);
    expect_no_lab_form_fits<RateDependence>(
        "rate_dependence", form, grid(0.5, 4.0, 60),
        [&](double v) { return forms::rate_factor(s, v, true); }, 1.0,
        [](const RateDependence& t, double v, const double* p) { return t.factor(v, p); },
        [](int f) { return RateDependence(2.0, f); },
        2);  // the last two say where it acts (at rest, before the puncture)
  }
  EXPECT_EQ(forms::rate_factor(slot(EffectKind::kRateDependence, "carreau"), 0.5, false), 1.0)
      << "Carreau acts on the cut only";
}

TEST(SimulatedForms, NoPressureLawIsOneOfTheLabsPressureLaws) {
  for (const std::string& form : effect_forms(EffectKind::kIopStiffness)) {
    if (form == "prestress") continue;  // moves the toe as well: below
    const EffectSlot s = slot(EffectKind::kIopStiffness, form);
    expect_no_lab_form_fits<IopStiffness>(
        "iop_stiffness", form, grid(-1.0, 4.0, 60),
        [&](double dp) { return forms::iop_change(s, 15.0 + dp).stiffness_factor; }, 1.0,
        [](const IopStiffness& t, double dp, const double* p) { return t.factor(dp, p); },
        [](int f) { return IopStiffness(f); });
  }
  // Pre-stress shortens the toe (the lab's "shorter toe" form, alone) and steepens the slopes
  // (the lab's other forms, alone): no one form of the lab does both.
  const forms::IopChange prestress =
      forms::iop_change(slot(EffectKind::kIopStiffness, "prestress"), 17.0);
  EXPECT_LT(prestress.toe_factor, 0.9);
  EXPECT_GT(prestress.stiffness_factor, 1.02);
}

TEST(SimulatedForms, NoRelaxationIsOneOfTheLabsRelaxations) {
  for (const std::string& form : effect_forms(EffectKind::kStressRelaxation)) {
    const EffectSlot s = slot(EffectKind::kStressRelaxation, form);
    expect_no_lab_form_fits<StressRelaxation>(
        "stress_relaxation", form, grid(0.0, 3.0, 150),
        [&](double t) { return forms::relaxed_fraction(s, t); }, 0.0,
        [](const StressRelaxation& r, double t, const double* p) { return r.decayed(t, p); },
        [](int f) { return StressRelaxation(f); },
        1);  // the last, `reload`, is how the tissue reloads after a stop
  }
}

// A technician may hold for minutes: every relaxation stays a fraction in [0, 0.9] that grows
// smoothly (the Mittag-Leffler form's exp(z^2) erfc(z) is inf x 0 past z ~ 26, 6 min: without
// its asymptote the fraction jumped from 0.28 to the 0.9 cap).
TEST(SimulatedForms, RelaxationStaysAFractionInHoldsOfAnyLength) {
  for (const std::string& form : effect_forms(EffectKind::kStressRelaxation)) {
    const EffectSlot s = slot(EffectKind::kStressRelaxation, form);
    double previous = 0.0;
    for (const double t : {0.001, 0.1, 1.0, 12.4, 12.6, 60.0, 600.0, 3600.0}) {
      const double fraction = forms::relaxed_fraction(s, t);
      EXPECT_TRUE(std::isfinite(fraction)) << form << " at " << t << " s";
      EXPECT_GE(fraction, previous - 1e-3) << form << " relaxes monotonically, at " << t << " s";
      if (t >= 60.0) {
        EXPECT_LT(fraction - previous, 0.2) << form << " jumps at " << t << " s";
      }
      EXPECT_LE(fraction, 0.9) << form;
      previous = fraction;
    }
  }
}

TEST(SimulatedForms, NoMountIsOneOfTheLabsMounts) {
  for (const std::string& form : effect_forms(EffectKind::kRigCompliance)) {
    const EffectSlot s = slot(EffectKind::kRigCompliance, form);
    expect_no_lab_form_fits<RigCompliance>(
        "rig_compliance", form, grid(0.0, 0.3, 60),
        [&](double f) { return forms::compliance_lag_mm(s, f); }, 0.0,
        [](const RigCompliance& m, double f, const double* p) { return m.lag(f, p); },
        [](int f) { return RigCompliance(f); });
  }
}

// The lab's friction laws in steady sliding, per inserted length [N/mm] against the speed v
// (shaft_friction.hpp): Coulomb-like forms mu; viscous eta v; both mu + eta v; breakaway
// mu + mu_s exp(-v / v_s). (The friction term's add() needs a prepared run; its laws in v are
// these.)
TEST(SimulatedForms, NoFrictionLawInTheSpeedIsOneOfTheLabsFrictionLaws) {
  struct LabLaw {
    std::string name;
    Bounds bounds;
    std::function<double(double, const double*)> law;
  };
  const std::vector<LabLaw> lab = {
      {"coulomb", {{-0.1}, {0.1}}, [](double, const double* p) { return p[0]; }},
      {"viscous", {{-0.05}, {0.05}}, [](double v, const double* p) { return p[0] * v; }},
      {"coulomb + viscous",
       {{-0.1, -0.05}, {0.1, 0.05}},
       [](double v, const double* p) { return p[0] + p[1] * v; }},
      {"static breakaway",
       {{-0.1, -0.1, 0.01}, {0.1, 0.2, 5.0}},
       [](double v, const double* p) { return p[0] + p[1] * std::exp(-v / p[2]); }},
  };
  for (const std::string form : {"coulomb_viscous", "stribeck"}) {
    const EffectSlot s = slot(EffectKind::kShaftFriction, form);
    for (const LabLaw& l : lab) {
      const double left = best_misfit(
          grid(0.5, 4.0, 60), [&](double v) { return forms::friction_per_mm(s, v); }, 0.0, l.law,
          l.bounds);
      std::printf("shaft_friction:%-16s against the lab's %-18s %.4f of the friction left over\n",
                  form.c_str(), l.name.c_str(), left);
      EXPECT_GT(left, kLeftOver) << form << " is the lab's " << l.name;
    }
  }
}

// The lab's thermal drift, offset + A (1 - exp(-t / tau)), fits each run's own A and offset.
TEST(SimulatedForms, TheSensorsWarmUpIsNotTheLabsFirstOrderThermalDrift) {
  const EffectSlot s = slot(EffectKind::kSensorDrift, "warmup");
  const Bounds b{{-0.1, -0.1, 0.1}, {0.1, 0.1, 60.0}};
  const double left = best_misfit(
      grid(0.0, 30.0, 300), [&](double t) { return forms::drift_N(s, t, 0.0); }, 0.0,
      [](double t, const double* p) { return p[0] + p[1] * -std::expm1(-t / p[2]); }, b);
  std::printf("sensor_drift:warmup against the lab's thermal %.4f of the drift left over\n", left);
  EXPECT_GT(left, kLeftOver);
}

// The lab's step form: each run's offset and slope in time and an ideal step at a sample of
// the run (the zoo samples at 1 kHz), its size fitted. The simulator's step rises over ~20 ms
// (a logistic of 5 ms); the step is put at every sample within 0.1 s of it and the best kept.
TEST(SimulatedForms, TheSensorsStepRisesOverMillisecondsUnlikeTheLabsIdealStep) {
  const EffectSlot s = slot(EffectKind::kSensorDrift, "step");
  const std::vector<double> ts = grid(0.0, 30.0, 30001);
  const double centre = 3.0 + 17.0 * s.run_values[1];  // where the simulator puts it [s]
  double best = 1e300;
  for (double at = centre - 0.1; at <= centre + 0.1; at += 0.001) {
    Eigen::Matrix3d a = Eigen::Matrix3d::Zero();
    Eigen::Vector3d b = Eigen::Vector3d::Zero();
    for (const double t : ts) {
      const Eigen::Vector3d row(1.0, t / 30.0, t >= at ? 1.0 : 0.0);
      a += row * row.transpose();
      b += row * forms::drift_N(s, t, 0.0);
    }
    const Eigen::Vector3d c = a.ldlt().solve(b);
    const auto law = [&](double t, const double*) {
      return c(0) + c(1) * t / 30.0 + (t >= at ? c(2) : 0.0);
    };
    best = std::min(
        best, misfit(
                  ts, [&](double t) { return forms::drift_N(s, t, 0.0); }, 0.0, law, nullptr));
  }
  std::printf("sensor_drift:step against the lab's offset steps %.4f of the step left over\n",
              best);
  EXPECT_GT(best, kLeftOver);
}

// The lab's speed-following tearing: a period P (v / 2 mm/s)^alpha [mm] (stick_slip.hpp).
TEST(SimulatedForms, TheTearsLengthInTheSpeedIsNotTheLabsPowerLaw) {
  const Bounds b{{0.05, -2.0}, {3.0, 2.0}};
  const double left = best_misfit(
      grid(0.5, 4.0, 60), [](double v) { return 1.0 / forms::tearing_cycles_per_mm(v); }, 0.0,
      [](double v, const double* p) { return p[0] * std::pow(v / 2.0, p[1]); }, b);
  std::printf("stick_slip:velocity_weakening period against the lab's power law %.4f left over\n",
              left);
  EXPECT_GT(left, kLeftOver);
}

// The lab's released tears (stick_slip.hpp, since 2026-12-07): after each release of the
// force a ramp, 2 min(d / L, 1) - 1 in the travel d since it, L shared (at one speed), each
// run its own amplitude. The simulator's aperiodic tears each build from -a to +a over their
// own length, 0.35 x U(0.4, 1.6) mm (tissue_truth.cpp, docs/sim.md): given every release
// exactly, the best amplitude and L still leave this share of the tearing.
TEST(SimulatedForms, AperiodicTearsOfTheirOwnLengthsAreNotTheLabsSharedRamp) {
  std::mt19937 rng(20261207);
  std::uniform_real_distribution<double> stretch(0.4, 1.6);
  std::vector<double> d, truth;  // travel since the release [mm], the tear's force [units of a]
  for (int tear = 0; tear < 300; ++tear) {
    const double length = 0.35 * stretch(rng);
    for (double x = 0.0; x < length; x += 0.002)
      d.push_back(x), truth.push_back(2.0 * x / length - 1.0);
  }
  double total = 0.0;
  for (const double f : truth) total += f * f;
  double best = 1.0;
  for (const double shared_mm : grid(0.05, 2.0, 400)) {
    double rr = 0.0, rt = 0.0;
    for (std::size_t k = 0; k < d.size(); ++k) {
      const double ramp = 2.0 * std::min(d[k] / shared_mm, 1.0) - 1.0;
      rr += ramp * ramp, rt += ramp * truth[k];
    }
    const double amplitude = rt / rr;
    double left = 0.0;
    for (std::size_t k = 0; k < d.size(); ++k) {
      const double e = truth[k] - amplitude * (2.0 * std::min(d[k] / shared_mm, 1.0) - 1.0);
      left += e * e;
    }
    best = std::min(best, left / total);
  }
  std::printf("stick_slip:aperiodic against the lab's released tears %.4f left over\n", best);
  EXPECT_GT(best, kLeftOver);
}

// The lab's tearing of a changing period (stick_slip.hpp, since 2026-12-07): 3 harmonics in
// the tears cut d mm past the puncture when the period is p exp(g d), each run its own
// coefficients. The simulator's tearing that grows with depth (effect_forms.cpp) over the
// first 5 mm of the cut, at the best p, g and coefficients, leaves this share of itself.
TEST(SimulatedForms, TearingThatGrowsAlongTheCutIsNotTheLabsExponentialPeriod) {
  const model::effects::StickSlip lab(model::effects::StickSlip::kGrowing);
  const EffectSlot growing = slot(EffectKind::kStickSlip, "growing");
  const std::vector<double> depths = grid(0.0, 5.0, 1000);  // past the puncture [mm]
  Eigen::VectorXd truth(static_cast<Eigen::Index>(depths.size()));
  for (std::size_t i = 0; i < depths.size(); ++i)
    truth(static_cast<Eigen::Index>(i)) = forms::tearing_pattern(growing, depths[i], 0.0);
  const auto left_over = [&](const double* p) {
    Eigen::MatrixXd rows(truth.size(), 6);
    for (std::size_t i = 0; i < depths.size(); ++i) {
      const double cycles = model::effects::StickSlip::growing_cycles(depths[i], p);
      for (int h = 1; h <= 3; ++h) {
        rows(static_cast<Eigen::Index>(i), 2 * h - 2) = std::sin(2.0 * M_PI * h * cycles);
        rows(static_cast<Eigen::Index>(i), 2 * h - 1) = std::cos(2.0 * M_PI * h * cycles);
      }
    }
    const Eigen::VectorXd fit = rows * rows.colPivHouseholderQr().solve(truth);
    return (truth - fit).squaredNorm() / truth.squaredNorm();
  };
  const Bounds b = bounds_of(lab.shared_params(), 2);
  const Coordinates c{&b};
  const auto f = [&](const std::vector<double>& u) { return left_over(c.params(u).data()); };
  std::vector<std::pair<double, std::vector<double>>>
      starts;  // the lab's own start grid, then Nelder-Mead
  for (const auto& start : lab.starts()) {
    const std::vector<double> u = {std::log(start[0]), start[1]};
    starts.emplace_back(f(u), u);
  }
  std::partial_sort(starts.begin(), starts.begin() + 10, starts.end(),
                    [](const auto& a, const auto& z) { return a.first < z.first; });
  double best = INFINITY;
  for (int k = 0; k < 10; ++k)
    best = std::min(best, nelder_mead(f, c, starts[static_cast<std::size_t>(k)].second));
  std::printf("stick_slip:growing against the lab's exponential period %.4f left over\n", best);
  EXPECT_GT(best, kLeftOver);
}

}  // namespace
}  // namespace rig::sim
