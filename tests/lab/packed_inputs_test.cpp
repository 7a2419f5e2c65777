// The diagnose-time shortcuts give the same numbers as the plain computation: packed sample
// inputs (one record per sample, the fit rows side by side), the run's depths looked up once,
// and Fourier harmonics by angle addition.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "effect_catalogue.hpp"
#include "effects/effect_util.hpp"
#include "force_model.hpp"
#include "lab_scenarios.hpp"
#include "model_family.hpp"
#include "predictor.hpp"
#include "prepared_run.hpp"

namespace rig::model {
namespace {

RunData standard_run(const std::vector<std::string>& hidden, std::uint64_t seed) {
  sim::GeneratorOptions g;
  for (const auto& name : hidden) {
    std::string error;
    g.effects.push_back(*sim::parse_hidden_effect(name, error));
  }
  sim::RunSpec spec;
  sim::apply_standard_protocol(spec);
  spec.seed = seed;
  spec.eye_id = "packed-" + std::to_string(seed);
  return sim::generate_run(g, spec);
}

TEST(PackedInputs, HoldEachSamplesOwnValuesAndTheFitRowsInOrder) {
  const RunData run = standard_run({"mains_interference"}, 3);
  const PreparedRun p = prepare_run(run, 400);
  ASSERT_EQ(p.inputs.size(), run.size());
  for (std::size_t i = 0; i < run.size(); ++i) {
    const SampleInputs& in = p.inputs[i];
    ASSERT_EQ(in.x_mm, run.x_mm[i]) << i;
    ASSERT_EQ(in.t_s, run.t_s[i]) << i;
    ASSERT_EQ(in.force_N, run.force_N[i]) << i;
    ASSERT_EQ(in.velocity_mm_s, p.velocity_mm_s[i]) << i;
    ASSERT_EQ(in.hold_s, p.hold_s[i])
        << i;  // stops on the way in included (set after derive_pauses)
    ASSERT_EQ(in.front_mm, p.front_mm[i]) << i;
    ASSERT_EQ(in.phase, p.seg.phase[i]) << i;
  }
  ASSERT_EQ(p.fit_inputs.size(), p.fit_rows.size());
  for (std::size_t n = 0; n < p.fit_rows.size(); ++n)
    ASSERT_EQ(p.fit_inputs[n].t_s, run.t_s[p.fit_rows[n]]) << n;
  // The grid's phase is tracked from first contact on.
  EXPECT_TRUE(std::isfinite(p.inputs[p.analysed.front()].grid_cycles[0]));
  EXPECT_TRUE(std::isfinite(p.inputs.back().grid_cycles[1]));
  double covered = 0.0;
  for (const double v : p.hold_s) covered += v > 0.0 ? 1.0 : 0.0;
  EXPECT_GT(covered, 1000.0);  // the run has its stops and hold: hold_s was not packed early
}

TEST(PackedInputs, GiveTheSamePredictionAsAnyOtherListOfTheSameRows) {
  std::vector<RunData> data = {standard_run({"mains_interference"}, 5),
                               standard_run({"spatial_ripple"}, 6)};
  std::vector<PreparedRun> prepared;
  for (const RunData& r : data) prepared.push_back(prepare_run(r, 300));
  std::vector<const PreparedRun*> runs = {&prepared[0], &prepared[1]};
  const ForceModel model = ForceModel::paper_interpreted();
  const EffectCatalogue catalogue(model, runs);
  const ModelFamily family(model, catalogue,
                           {"mains_interference", "spatial_ripple", "sensor_drift"});
  const Predictor& predictor = family.predictor();
  const ModelParams p = family.start(runs);
  for (PreparedRun& run : prepared) {
    // The fit rows' packed path, against the same rows as another vector (the general path).
    const std::vector<std::size_t> copy = run.fit_rows;
    std::vector<double> packed, general;
    Eigen::MatrixXd x_packed, x_general;
    predictor.evaluate(run, p, run.fit_rows, packed, &x_packed);
    predictor.evaluate(run, p, copy, general, &x_general);
    ASSERT_EQ(packed.size(), copy.size());
    EXPECT_EQ(packed, general);
    EXPECT_TRUE(x_packed.cwiseEqual(x_general).all());
    // Fit rows changed (a within-run fold): once repacked, the packed path follows them.
    run.fit_rows.assign(copy.begin(), copy.begin() + static_cast<std::ptrdiff_t>(copy.size() / 2));
    pack_fit_rows(run);
    const std::vector<std::size_t> half = run.fit_rows;
    predictor.evaluate(run, p, run.fit_rows, packed);
    predictor.evaluate(run, p, half, general);
    EXPECT_EQ(packed, general);
  }
}

TEST(ForceModel, BaselineWithTheRunsDepthsLookedUpOnceIsTheBaselineAtThatIop) {
  ForceModel m = ForceModel::paper_interpreted();
  m.params.x_pi_shift = 0.2;
  for (const double iop : {14.0, 15.0, 16.3, 18.0, 21.0}) {
    const ForceModel::RunDepths d = m.depths(iop);
    EXPECT_EQ(d.x_pi_mm, m.puncture_depth_mm(iop));
    EXPECT_EQ(d.x_pf_mm, m.final_depth_mm(iop));
    for (double front = -0.5; front <= 12.0; front += 0.37) {
      for (double x = -1.0; x <= front + 0.5; x += 0.29) {
        // Held or withdrawn: the force reached at the front, released over w_release.
        const double release =
            std::max(0.0, 1.0 - (front - x) / std::max(m.params.w_release, 1e-4));
        const double expected = x >= front ? m.baseline(x, iop) : m.baseline(front, iop) * release;
        ASSERT_DOUBLE_EQ(m.baseline(x, front, d), expected) << iop << " " << front << " " << x;
        ASSERT_DOUBLE_EQ(m.baseline(x, front, iop), expected);
      }
    }
  }
}

TEST(Fourier, HarmonicsByAngleAdditionAreSinAndCosOfEachHarmonic) {
  // Up to 2,100 cycles: 60 Hz over a 35 s run.
  for (const double cycles : {0.0, 0.123, -3.7, 17.25, 999.999, 2100.3}) {
    double row[10];
    effects::fourier(cycles, 5, row);
    for (int k = 1; k <= 5; ++k) {
      const double a = 2.0 * std::numbers::pi * k * cycles;
      EXPECT_NEAR(row[2 * (k - 1)], std::sin(a), 1e-9) << cycles << " harmonic " << k;
      EXPECT_NEAR(row[2 * (k - 1) + 1], std::cos(a), 1e-9) << cycles << " harmonic " << k;
    }
  }
}

}  // namespace
}  // namespace rig::model
