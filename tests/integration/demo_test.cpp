// The README's first command: `rig demo --once --format json` on the simulated rig.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>

#include "rig/sim/physics_params.hpp"
#include "command.hpp"
#include "test_paths.hpp"

namespace rig {
namespace {

TEST(Demo, OnceAsJsonCutsTwoThousandSamplesPerMillimetreAndFindsThePeakWhereTheTruthPutsIt) {
  testing::ScratchDir dir("demo");
  const std::string command = testing::bin("rig") + " --format json demo --once --port 0 --sim " + testing::bin("rig-sim") +
                              " --rigd " + testing::bin("rigd") + " --config " + testing::source("config/rigd.sim.toml") +
                              " --state-dir " + dir.path().string();
  const testing::CommandResult demo = testing::run_command(command, false);
  ASSERT_EQ(demo.exit_code, 0) << demo.output;
  const auto j = nlohmann::json::parse(demo.output);
  for (const char* key : {"run_id", "samples", "velocity_mean_mm_s", "velocity_error_pct", "peak_force_N", "x_at_peak_mm"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_GE(j["samples"].get<int>(), 5000);
  EXPECT_LT(std::abs(j["velocity_error_pct"].get<double>()), 1.0);
  // The simulated eye: x_pi(15 mmHg) from Table 1, shifted by this eye's own puncture depth
  // (eyes differ by default, 1 sigma = eye_puncture_sigma_mm): within 3 sigma + 0.1 mm.
  const sim::TissueParams truth;
  EXPECT_NEAR(j["x_at_peak_mm"].get<double>(), truth.table_xpi_mm[0], 0.1 + 3.0 * truth.eye_puncture_sigma_mm * truth.eye_variability);
  EXPECT_LT(j["model_rmse_N"].get<double>(), 0.01);
}

}  // namespace
}  // namespace rig
