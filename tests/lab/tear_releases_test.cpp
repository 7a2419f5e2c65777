// The tear-release detector (tear_releases.hpp) on synthetic cuts: 1 kHz, 1.5 mN white noise
// (the zoo's load cell), the carriage at 2 mm/s, every sample past the puncture.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "tear_releases.hpp"

namespace rig::model::tear_release_test {
namespace {

constexpr double kRate_Hz = 1000.0;
constexpr double kNoise_N = 0.0015;
constexpr double kSpeed_mm_s = 2.0;

struct SyntheticCut {
  RunData run;
  Segmentation seg;
  std::vector<double> velocity_mm_s;
  std::vector<std::size_t> releases;  // the last sample before each true release
};

// 4 s of cutting from 2 mm on; tears of random lengths 0.14-0.56 mm building `amplitude_N`
// each (0 for none); the carriage stands still from 1.5 to 2.0 s while the force relaxes by
// `relax_N` within 2 ms of stopping.
SyntheticCut cut(double amplitude_N, double relax_N, unsigned seed) {
  SyntheticCut c;
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, kNoise_N);
  std::uniform_real_distribution<double> length(0.14, 0.56);
  double tear_from = 2.0, tear_to = 2.0 + length(rng), x = 2.0;
  for (int k = 0; k < 4000; ++k) {
    const double t = k / kRate_Hz;
    const bool stopped = t >= 1.5 && t < 2.0;
    if (k > 0 && !stopped) x += kSpeed_mm_s / kRate_Hz;
    if (x >= tear_to) {
      c.releases.push_back(static_cast<std::size_t>(k - 1));
      tear_from = tear_to, tear_to += length(rng);
    }
    const double tear = amplitude_N * (2.0 * (x - tear_from) / (tear_to - tear_from) - 1.0);
    const double relaxed = t >= 1.5 ? relax_N * (1.0 - std::exp(-(t - 1.5) / 0.002)) : 0.0;
    c.run.t_s.push_back(t);
    c.run.x_mm.push_back(x);
    c.run.force_N.push_back(0.2 + tear - relaxed + noise(rng));
    c.velocity_mm_s.push_back(stopped ? 0.0 : kSpeed_mm_s);
  }
  c.seg.phase.assign(c.run.size(), Phase::kCutting);
  c.seg.punctured = true;
  c.seg.x_pi_mm = 1.5;
  c.seg.noise_sigma_N = kNoise_N;
  return c;
}

TEST(TearReleases, EveryReleaseOfAperiodicTearingIsFoundWithinTwoSamples) {
  const SyntheticCut c = cut(0.006, 0.0, 3);
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  ASSERT_EQ(found.at.size(), c.releases.size());
  for (std::size_t k = 0; k < found.at.size(); ++k) {
    EXPECT_LE(std::abs(static_cast<double>(found.at[k]) - static_cast<double>(c.releases[k])), 2.0)
        << "release " << k;
    EXPECT_NEAR(found.drop_N[k], 0.012, 0.004) << "release " << k;  // a 6 mN tear lets go of 12 mN
  }
}

TEST(TearReleases, NoiseAloneAndAStopThatRelaxesTheForceAtOnceReleaseNothing) {
  const SyntheticCut c = cut(0.0, 0.02, 5);
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  EXPECT_TRUE(found.at.empty()) << found.at.size() << " releases, the first at sample "
                                << (found.at.empty() ? 0 : found.at.front());
  for (const double since : found.since_mm) EXPECT_LT(since, 0.0);
}

// A sample's travel since the release is read off samples before it only: the window that
// shows a drop ends 5 samples after it, so the release counts from the 6th sample on.
TEST(TearReleases, ASampleSeesOnlyReleasesItsPastShows) {
  const SyntheticCut c = cut(0.006, 0.0, 3);
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  ASSERT_GE(found.at.size(), 3U);
  const std::size_t second = found.at[1];
  const double before_known = found.since_mm[second + 5];
  const double once_known = found.since_mm[second + 6];
  EXPECT_GT(before_known, c.run.x_mm[second + 5] - c.run.x_mm[found.at[0] + 1] -
                              1e-9);  // still the first release's
  EXPECT_NEAR(once_known, c.run.x_mm[second + 6] - c.run.x_mm[second + 1], 1e-9);
}

TEST(TearReleases, WithdrawingEndsTheTearThatWasBuilding) {
  SyntheticCut c = cut(0.006, 0.0, 3);
  for (std::size_t i = 3500; i < c.seg.phase.size(); ++i) c.seg.phase[i] = Phase::kRetraction;
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  EXPECT_GE(found.since_mm[3499], 0.0);
  EXPECT_LT(found.since_mm[3500], 0.0);
  EXPECT_LT(found.since_mm.back(), 0.0);
}

// The puncture's own drop, right past the puncture the data show, and a lone slip later on
// are not tearing: a run needs three drops for tears, none of them within 0.3 mm of it.
TEST(TearReleases, ThePuncturesOwnDropAndALoneSlipAreNoTears) {
  SyntheticCut c = cut(0.0, 0.0, 5);
  c.seg.x_pi_mm = 1.95;
  for (std::size_t i = 0; i < c.run.size(); ++i) {
    if (c.run.x_mm[i] > 2.1) c.run.force_N[i] -= 0.03;  // the puncture's drop, 0.15 mm past it
    if (c.run.t_s[i] > 3.0) c.run.force_N[i] -= 0.03;   // one slip
  }
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  EXPECT_TRUE(found.at.empty()) << found.at.size() << " releases";
}

// A drop far above one sample's noise is known from the sample after the next: tears that
// let go within a sample mispredict one sample, not six.
TEST(TearReleases, ALargeDropIsKnownTwoSamplesAfterItNotSix) {
  const SyntheticCut c = cut(0.03, 0.0, 3);  // 60 mN drops, 28 sigmas of a one-sample difference
  const TearReleases found = find_tear_releases(c.run, c.seg, c.velocity_mm_s, kSpeed_mm_s);
  ASSERT_EQ(found.at.size(), c.releases.size());
  for (std::size_t k = 0; k < found.at.size(); ++k)
    EXPECT_EQ(found.known[k], found.at[k] + 2) << "release " << k;
  const std::size_t second = found.at[1];
  EXPECT_NEAR(found.since_mm[second + 2], c.run.x_mm[second + 2] - c.run.x_mm[second + 1], 1e-9);
  EXPECT_GT(found.since_mm[second + 1], 0.1);  // still the first tear's travel
}

}  // namespace
}  // namespace rig::model::tear_release_test
