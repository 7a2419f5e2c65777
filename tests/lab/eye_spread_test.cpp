// The eyes' spread by the method of moments (eye_variation.hpp): parameters fitted on one
// value per eye take their degrees of freedom from it, as a sample variance's mean takes one.
#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <cstdio>
#include <random>
#include <vector>

#include "eye_variation.hpp"

namespace rig::model {
namespace {

// Mean over many sets of nine eyes of the estimated tau^2, each eye's parameter a quadratic
// law in a covariate (level, slope, curvature: 3 parameters fitted on one value per eye) plus
// its own deviation (SD tau) and a measurement error of known variance; `counted` is the
// number of fitted parameters the estimate is told of.
double mean_estimated_variance(double tau, int counted) {
  constexpr int kEyes = 9, kSets = 4000;
  std::mt19937 rng(2026);
  std::normal_distribution<double> unit(0.0, 1.0);
  Eigen::MatrixXd design(kEyes, 3);
  for (int r = 0; r < kEyes; ++r) {
    const double z = -1.0 + 2.0 * r / (kEyes - 1.0);  // the covariate over its spread [1]
    design.row(r) << 1.0, z, z * z;
  }
  double sum = 0.0;
  for (int set = 0; set < kSets; ++set) {
    Eigen::VectorXd value(kEyes);
    std::vector<double> variances(kEyes);
    for (int r = 0; r < kEyes; ++r) {
      variances[r] = 0.02 * 0.02 * (0.5 + r % 3);  // each eye's sampling variance [1]
      value(r) = 0.05 + 0.2 * design(r, 1) - 0.1 * design(r, 2) + tau * unit(rng) +
                 std::sqrt(variances[r]) * unit(rng);
    }
    const Eigen::VectorXd fitted = design * design.colPivHouseholderQr().solve(value);
    std::vector<double> deviations(kEyes);
    for (int r = 0; r < kEyes; ++r) deviations[r] = value(r) - fitted(r);
    sum += eye_parameter_variance(deviations, variances, counted);
  }
  return sum / kSets;
}

TEST(EyeSpread, ParametersFittedOnOneValuePerEyeTakeTheirDegreesOfFreedomFromIt) {
  constexpr double kTau = 0.1;  // the eyes' true spread of a relative scale [1]
  const double counted = mean_estimated_variance(kTau, 3);
  const double ignored = mean_estimated_variance(kTau, 0);
  std::printf("tau^2 = %.5f; estimated %.5f with the 3 fitted parameters counted, %.5f without\n",
              kTau * kTau, counted, ignored);
  EXPECT_NEAR(counted, kTau * kTau, 0.05 * kTau * kTau)
      << "unbiased once the fitted parameters are counted";
  EXPECT_LT(ignored, 0.75 * kTau * kTau)
      << "6/9 of the truth when they are not (the contrast this test rests on)";
}

TEST(EyeSpread, IsZeroWhenTheDeviationsAreNoLargerThanTheirOwnSamplingError) {
  EXPECT_EQ(eye_parameter_variance({0.01, -0.01, 0.0}, {0.01, 0.01, 0.01}, 1), 0.0);
  EXPECT_EQ(eye_parameter_variance({}, {}, 1), 0.0);
  // More parameters than eyes: one degree of freedom is left, never zero or fewer.
  EXPECT_NEAR(eye_parameter_variance({0.3, -0.3}, {0.0, 0.0}, 5), 0.18, 1e-12);
}

}  // namespace
}  // namespace rig::model
