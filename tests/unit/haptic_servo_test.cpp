// The haptic servo's pieces on their own: the estimate between encoder counts, the safety
// chain (clamp, ramp-in, slew, NaN/inf guard, guide spring), the stiffness check and the
// mass-spring cornea.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "encoder_estimator.hpp"
#include "haptic_session.hpp"
#include "mass_spring_cornea.hpp"
#include "servo_loop.hpp"

namespace rig::haptic {
namespace {

class ConstantSource final : public ForceSource {
 public:
  explicit ConstantSource(double force_N) : force_N_(force_N) {}
  double force_N(double depth_mm, double, double) const noexcept override {
    return depth_mm > 0.0 ? force_N_ : 0.0;
  }
  const char* describe() const noexcept override { return "constant"; }
  double force_N_;
};

class StiffSource final : public ForceSource {
 public:
  double force_N(double depth_mm, double, double) const noexcept override {
    return depth_mm > 0.0 ? 2.0 * depth_mm : 0.0;
  }
  const char* describe() const noexcept override { return "stiff spring"; }
};

constexpr drivers::HapticLimits kOmni{3.3, 0.88, 0.7};

ServoSettings plain_settings() {
  ServoSettings s;
  s.surface_mm = drivers::Vec3{0.0, 0.0, 0.0};
  s.ramp_in_s = 0.0;
  s.mesh_enabled = false;
  s.count_late_ticks = false;
  return s;
}

// Position [mm] for a tip `depth` into the eye along the default axis (-z).
drivers::Vec3 at_depth(double depth_mm) {
  return {0.0, 0.0, -depth_mm};
}

// Runs ticks at 1 kHz with the tip at `depth`, returns the last axial force (+ resists).
double hold_at(ServoLoop& servo, double depth_mm, int ticks, double& t_s) {
  drivers::Vec3 force{};
  for (int i = 0; i < ticks; ++i, t_s += 0.001) force = servo.tick(at_depth(depth_mm), t_s);
  return force[2];
}

TEST(EncoderEstimator, RecoversAConstantVelocityBetweenCountsToAFractionOfOneCount) {
  EncoderEstimator estimator(0.055, 0.0);
  double worst_mm = 0.0;
  for (int k = 0; k < 5000; ++k) {
    const double t = k * 0.001, truth = 2.0 * t;
    const double raw = std::round(truth / 0.055) * 0.055;
    const double estimate = estimator.update(raw, t);
    if (t > 0.1) worst_mm = std::max(worst_mm, std::abs(estimate - truth));
  }
  EXPECT_LT(worst_mm, 0.003);  // the raw count is off by up to 0.0275 mm
  EXPECT_NEAR(estimator.velocity_mm_s(), 2.0, 0.05);
}

TEST(EncoderEstimator, StopsExtrapolatingWhenTheHandReversesAndNeverLeavesTheCurrentCell) {
  EncoderEstimator estimator(0.055, 0.0);
  double t = 0.0;
  for (int k = 0; k < 1000; ++k, t += 0.001)
    estimator.update(std::round(2.0 * t / 0.055) * 0.055, t);
  const double top = 2.0 * t;
  for (int k = 0; k < 1000; ++k, t += 0.001) {
    const double truth = top - 2.0 * (k * 0.001);
    const double raw = std::round(truth / 0.055) * 0.055;
    const double estimate = estimator.update(raw, t);
    EXPECT_LE(std::abs(estimate - raw), 0.0276) << "at " << t << " s";
  }
  EXPECT_LT(estimator.velocity_mm_s(), 0.0);
}

TEST(ServoLoop, NeverCommandsMoreThanTheContinuousForceTheDeviceReports) {
  ConstantSource source(10.0);
  ServoSettings settings = plain_settings();
  settings.max_slew_N_per_s = 1e6;
  ServoLoop servo(settings, source, kOmni);
  double t = 0.0;
  EXPECT_NEAR(hold_at(servo, 1.0, 50, t), 0.88, 1e-12);
  EXPECT_GT(servo.counters().clamped_ticks.load(), 0U);
  drivers::HapticLimits weaker = kOmni;
  weaker.max_continuous_force_N = 0.5;
  ServoLoop weaker_servo(settings, source, weaker);
  t = 0.0;
  EXPECT_NEAR(hold_at(weaker_servo, 1.0, 50, t), 0.5, 1e-12);
}

TEST(ServoLoop, RampsTheForceInOverHalfASecondFromTheFirstTick) {
  ConstantSource source(0.4);
  ServoSettings settings = plain_settings();
  settings.ramp_in_s = 0.5;
  ServoLoop servo(settings, source, kOmni);
  double t = 0.0;
  const double first = hold_at(servo, 1.0, 1, t);
  const double quarter = hold_at(servo, 1.0, 249, t);  // t = 0.249 s at the last tick
  const double full = hold_at(servo, 1.0, 400, t);
  EXPECT_NEAR(first, 0.0, 1e-12);
  EXPECT_NEAR(quarter, 0.4 * 0.249 / 0.5, 0.002);
  EXPECT_NEAR(full, 0.4, 1e-12);
}

TEST(ServoLoop, LimitsHowFastTheForceMayChange) {
  ConstantSource source(0.8);
  ServoSettings settings = plain_settings();
  settings.max_slew_N_per_s = 50.0;
  ServoLoop servo(settings, source, kOmni);
  double t = 0.0;
  hold_at(servo, -1.0, 10, t);  // outside: 0 N
  const double one_tick = hold_at(servo, 1.0, 1, t);
  EXPECT_NEAR(one_tick, 0.05, 1e-9);  // 50 N/s over 1 ms
  EXPECT_NEAR(hold_at(servo, 1.0, 20, t), 0.8, 1e-9);
  EXPECT_GT(servo.counters().slew_limited_ticks.load(), 0U);
}

TEST(ServoLoop, RendersZeroForceForANanOrInfiniteSourceAndCountsIt) {
  for (const double bad :
       {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity(),
        -std::numeric_limits<double>::infinity()}) {
    ConstantSource source(bad);
    ServoLoop servo(plain_settings(), source, kOmni);
    double t = 0.0;
    drivers::Vec3 force{};
    for (int i = 0; i < 10; ++i, t += 0.001) force = servo.tick(at_depth(1.0), t);
    for (const double c : force) EXPECT_EQ(c, 0.0);
    EXPECT_EQ(servo.counters().nonfinite_forces.load(), 10U);
  }
}

TEST(ServoLoop, TreatsANanPositionAsNoForce) {
  ConstantSource source(0.3);
  ServoLoop servo(plain_settings(), source, kOmni);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  double t = 0.0;
  EXPECT_NEAR(hold_at(servo, 1.0, 10, t), 0.3, 1e-12);
  const drivers::Vec3 force = servo.tick({nan, 0.0, nan}, t);
  for (const double c : force) EXPECT_EQ(c, 0.0);
  EXPECT_EQ(servo.counters().nonfinite_positions.load(), 1U);
  t += 0.001;
  EXPECT_NEAR(hold_at(servo, 1.0, 10, t), 0.3, 1e-12);  // the estimate was not poisoned
}

TEST(ServoLoop, PushesTheBladeBackOutAlongItsAxisAndNothingOutsideTheEye) {
  ConstantSource source(0.2);
  ServoSettings settings = plain_settings();
  settings.axis = {1.0, 0.0, 0.0};
  ServoLoop servo(settings, source, kOmni);
  double t = 0.0;
  drivers::Vec3 outside{}, inside{};
  for (int i = 0; i < 10; ++i, t += 0.001) outside = servo.tick({-0.5, 0.0, 0.0}, t);
  for (int i = 0; i < 10; ++i, t += 0.001) inside = servo.tick({0.5, 0.0, 0.0}, t);
  EXPECT_EQ(outside[0], 0.0);
  EXPECT_NEAR(inside[0], -0.2, 1e-12);
}

TEST(ServoLoop, HoldsTheBladeOnItsAxisInTissueWithACappedGuideSpring) {
  ConstantSource source(0.0);
  ServoLoop servo(plain_settings(), source, kOmni);
  const drivers::Vec3 small = servo.tick({0.5, 0.0, -1.0}, 0.0);  // 0.5 mm off-axis, 1 mm deep
  EXPECT_NEAR(small[0], -0.3 * 0.5, 1e-12);
  const drivers::Vec3 large = servo.tick({50.0, 0.0, -1.0}, 0.001);
  EXPECT_NEAR(std::hypot(large[0], large[1]), 0.88, 1e-9);
}

TEST(ServoLoop, RefusesAnAxisOfZeroLengthAndADeviceWithoutLimits) {
  ConstantSource source(0.1);
  ServoSettings settings = plain_settings();
  settings.axis = {0.0, 0.0, 0.0};
  EXPECT_THROW(ServoLoop(settings, source, kOmni), std::invalid_argument);
  EXPECT_THROW(ServoLoop(plain_settings(), source, drivers::HapticLimits{}), std::invalid_argument);
}

TEST(CheckRenderable, RefusesASourceStifferThanTheDeviceNamingBothStiffnesses) {
  StiffSource stiff;
  try {
    check_renderable(stiff, kOmni);
    FAIL() << "a 2 N/mm spring passed on a 0.7 N/mm device";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("2.00 N/mm"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("HD_NOMINAL_MAX_STIFFNESS"), std::string::npos)
        << e.what();
  }
  drivers::HapticLimits stiff_device = kOmni;
  stiff_device.max_stiffness_N_per_mm = 3.0;
  EXPECT_NO_THROW(check_renderable(stiff, stiff_device));
}

TEST(MassSpringCornea, HasThePapersVerticesAndSpringsByDefaultAndScalesWithN) {
  MassSpringCornea paper(MeshSettings{});
  EXPECT_EQ(paper.vertex_count(), 169);
  EXPECT_EQ(paper.spring_count(), 886);
  MeshSettings bigger;
  bigger.n = 41;
  MassSpringCornea ten_times(bigger);
  EXPECT_EQ(ten_times.vertex_count(), 1681);
  EXPECT_EQ(ten_times.spring_count(), 2 * 41 * 40 + 2 * 40 * 40 + 2 * 41 * 39);
}

TEST(MassSpringCornea, FollowsTheTipUntilThePunctureThenTheCutOpensAndTheTissueRelaxes) {
  MeshSettings settings;
  MassSpringCornea mesh(settings);
  for (int i = 0; i < 2000; ++i) mesh.step(0.001, 1.0, false);
  EXPECT_NEAR(mesh.depth_at_centre_mm(), 1.0, 1e-9);
  double x[64], z[64];
  const int n = mesh.cross_section(x, z, 64);
  ASSERT_EQ(n, 13);
  EXPECT_GT(z[5], 0.2);  // the neighbours are dragged down with the tip
  EXPECT_EQ(mesh.active_spring_count(), 886);
  for (int i = 0; i < 2000; ++i) mesh.step(0.001, 1.0, true);
  EXPECT_LT(mesh.active_spring_count(), 886);
  EXPECT_LT(mesh.depth_at_centre_mm(), 0.5);  // released: the cut edges spring back
  mesh.cross_section(x, z, 64);
  EXPECT_LE(x[6], -settings.blade_thickness_mm / 2.0 + 1e-9);  // held open by the blade
}

}  // namespace
}  // namespace rig::haptic
