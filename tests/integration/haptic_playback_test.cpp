// Haptic playback end to end in one process: the simulated Phantom with a virtual hand
// against the model and a recorded run (the paper's fidelity figures), the stall watchdog
// on a real-time servo, and the OpenHaptics path through dlopen: a missing library, a
// library that is not libHD, and a stand-in libHD with the real C ABI (tests/support).
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "felt_error.hpp"
#include "haptic/openhaptics_device.hpp"
#include "haptic_session.hpp"
#include "model_force_source.hpp"
#include "playback.hpp"
#include "recorded_run_source.hpp"
#include "run_generator.hpp"
#include "servo_loop.hpp"
#include "sim_phantom.hpp"
#include "test_paths.hpp"
#include "virtual_hand.hpp"

namespace rig::haptic {
namespace {

PlaybackResult play_model(double velocity_mm_s, double iop_mmHg) {
  PlaybackOptions o;
  o.velocity_mm_s = velocity_mm_s;
  o.iop_mmHg = iop_mmHg;
  o.real_time = false;
  Playback playback(o, model::ForceModel::paper_interpreted(), std::nullopt);
  return playback.run(nullptr, nullptr);
}

TEST(HapticPlayback, TheSimulatedPhantomAt2MmPerSecondAndIop15FeelsTheModelBetterThanThePaper) {
  const PlaybackResult result = play_model(2.0, 15.0);
  ASSERT_TRUE(result.vs_model);
  const ErrorFigures& e = *result.vs_model;
  std::printf(
      "haptic vs model at 2 mm/s, IOP 15: RMSE %.5f N, max %.5f N at %.3f mm over %zu ticks in "
      "contact\n",
      e.rmse_N, e.max_N, e.max_at_depth_mm, e.samples);
  EXPECT_GT(e.samples, 9000U);  // 9.85 mm in and out at 2 mm/s
  EXPECT_LT(e.rmse_N, 0.004);   // the paper's figures
  EXPECT_LT(e.max_N, 0.016);
  EXPECT_LT(e.rmse_N, 0.001);  // our aim
  EXPECT_LT(e.max_N, 0.005);
  EXPECT_EQ(result.report.nonfinite_forces, 0U);
  EXPECT_EQ(result.report.clamped_ticks, 0U);
  EXPECT_EQ(result.report.mesh_vertices, 169);
  EXPECT_EQ(result.report.mesh_springs, 886);
}

TEST(HapticPlayback, StaysWithinThePapersFiguresAcrossTheRigsVelocitiesAndPressures) {
  for (const double v : {0.5, 4.0}) {
    for (const double iop : {15.0, 18.0}) {
      const PlaybackResult result = play_model(v, iop);
      EXPECT_LT(result.vs_model->rmse_N, 0.004) << v << " mm/s, IOP " << iop;
      EXPECT_LT(result.vs_model->max_N, 0.016) << v << " mm/s, IOP " << iop;
    }
  }
}

// The same session with the raw encoder counts rendered: the error metric must see it.
TEST(HapticPlayback, RenderingTheRawEncoderCountsWouldBeSeveralTimesWorse) {
  const model::ForceModel model = model::ForceModel::paper_interpreted();
  ModelForceSource source(model, 15.0);
  drivers::PushingHand hand(2.0, 9.85);
  drivers::SimPhantomSettings settings;
  settings.real_time = false;
  drivers::SimPhantom device(settings, hand);
  ServoSettings servo;
  servo.surface_mm = drivers::Vec3{0.0, 0.0, 0.0};
  servo.estimate_between_counts = false;
  // Virtual time: the session arms no wall-clock watchdog. With a 20 ms one, a loaded machine
  // ended this session before contact (raw max 0 N).
  HapticSession session(device, source, servo);
  const SessionReport report = session.run(nullptr, nullptr, 60.0);
  ASSERT_TRUE(report.fault.empty()) << report.fault;
  const ErrorFigures raw = felt_error(device.felt(), source);
  EXPECT_GT(raw.samples, 9000U);  // 9.85 mm in and out at 2 mm/s, as the estimated session
  const ErrorFigures estimated = *play_model(2.0, 15.0).vs_model;
  std::printf("raw counts: RMSE %.5f N, max %.5f N; estimated: RMSE %.5f N, max %.5f N\n",
              raw.rmse_N, raw.max_N, estimated.rmse_N, estimated.max_N);
  EXPECT_GT(raw.max_N, 5.0 * estimated.max_N);
}

TEST(HapticPlayback, ARecordedRunIsFeltAsItsForceDisplacementCurveAndComparedWithTheModel) {
  sim::RunSpec spec;
  spec.depth_mm = 10.0;
  spec.eye_id = "HAPTIC-1";
  const model::RunData run = sim::generate_run(sim::GeneratorOptions{}, spec);
  PlaybackOptions o;
  o.source = SourceSpec::parse("run:HAPTIC-1");
  o.real_time = false;
  Playback playback(o, model::ForceModel::paper_interpreted(), run);
  const PlaybackResult result = playback.run(nullptr, nullptr);
  ASSERT_TRUE(result.vs_run && result.vs_model);
  std::printf(
      "run source: haptic vs run RMSE %.5f N, max %.5f N; vs model RMSE %.5f N, max %.5f N\n",
      result.vs_run->rmse_N, result.vs_run->max_N, result.vs_model->rmse_N, result.vs_model->max_N);
  EXPECT_LT(result.vs_run->rmse_N, 0.004);
  EXPECT_LT(result.vs_run->max_N, 0.016);
  EXPECT_GT(result.vs_model->rmse_N, result.vs_run->rmse_N);  // the run is not the model
}

class BlockingSource final : public ForceSource {
 public:
  double force_N(double depth_mm, double, double) const noexcept override {
    if (armed_.load() && depth_mm > 0.5 && !blocked_.exchange(true))
      std::this_thread::sleep_for(std::chrono::milliseconds(150));
    return depth_mm > 0.0 ? 0.05 * depth_mm : 0.0;  // 0.05 N/mm: renderable
  }
  const char* describe() const noexcept override { return "blocking"; }
  std::atomic<bool> armed_{false};  // not while the session checks the source at setup
  mutable std::atomic<bool> blocked_{false};
};

TEST(HapticPlayback, TheWatchdogTurnsForceOffWhenTheServoStalls) {
  BlockingSource source;
  drivers::PushingHand hand(4.0, 1.0, -0.2, 0.2);
  drivers::SimPhantom device(drivers::SimPhantomSettings{}, hand);
  ServoSettings servo;
  servo.surface_mm = drivers::Vec3{0.0, 0.0, 0.0};
  HapticSession session(device, source, servo, std::chrono::milliseconds(20));
  source.armed_ = true;
  const SessionReport report = session.run(nullptr, nullptr, 10.0);
  EXPECT_TRUE(report.watchdog_tripped);
  EXPECT_TRUE(device.forced_off());
  EXPECT_GE(report.longest_stall_ms, 20.0);
  EXPECT_NE(report.fault.find("stalled"), std::string::npos) << report.fault;
}

// On virtual time no hand holds the device: a stall of the servo thread (a loaded machine)
// must not end the session, which a 20 ms wall-clock watchdog did under ./rig stress. The
// session decides from the device, whatever watchdog its caller asks for.
TEST(HapticPlayback, AVirtualTimeSessionHasNoWallClockWatchdogWhateverTheCallerAsks) {
  BlockingSource source;
  drivers::PushingHand hand(4.0, 1.0, -0.2, 0.2);
  drivers::SimPhantomSettings settings;
  settings.real_time = false;
  drivers::SimPhantom device(settings, hand);
  ServoSettings servo;
  servo.surface_mm = drivers::Vec3{0.0, 0.0, 0.0};
  HapticSession session(device, source, servo, std::chrono::milliseconds(20));
  source.armed_ = true;
  const SessionReport report = session.run(nullptr, nullptr, 10.0);
  EXPECT_TRUE(source.blocked_.load()) << "the source never stalled the servo";
  EXPECT_FALSE(report.watchdog_tripped);
  EXPECT_TRUE(report.fault.empty()) << report.fault;
  EXPECT_FALSE(device.forced_off());
}

// The watchdog is judged against the servo's own clock. On these VMs a SCHED_FIFO thread still
// wakes up to 11-19 ms late now and then (docs/haptics.md), and under the ASan tier beside two
// builds the servo was once really silent for more than 20 ms (CI, 2026-12-07: tripped after
// 636 ticks). Then tripping is right: the watchdog must only never blame a servo that ticked.
// A session the machine left alone must run to its end quietly, and one of three must be one.
TEST(HapticPlayback, TheWatchdogStaysQuietWhileTheServoTicksAndTripsOnlyWhenItWasReallySilent) {
  constexpr double kTimeoutMs = 20.0;    // HapticSession's default watchdog [ms]
  constexpr double kClockSlackMs = 1.0;  // tick start vs. tick count, under a sanitizer [ms]
  std::string stalled;
  bool quiet_session = false;
  for (int attempt = 0; attempt < 3 && !quiet_session; ++attempt) {
    PlaybackOptions o;
    o.velocity_mm_s = 4.0;
    o.depth_mm = 1.0;
    Playback playback(o, model::ForceModel::paper_interpreted(), std::nullopt);
    const SessionReport r = playback.run(nullptr, nullptr).report;
    if (r.watchdog_tripped) {
      EXPECT_GE(r.longest_tick_gap_ms, kTimeoutMs - kClockSlackMs)
          << "the watchdog blamed a servo whose own longest gap was " << r.longest_tick_gap_ms
          << " ms (it saw " << r.longest_stall_ms << " ms)";
      EXPECT_NE(r.fault.find("stalled"), std::string::npos) << r.fault;
      stalled += " " + std::to_string(r.longest_tick_gap_ms) + " ms";
      continue;
    }
    quiet_session = true;
    EXPECT_TRUE(r.fault.empty()) << r.fault;
    EXPECT_GT(r.ticks, 1000U);
    EXPECT_GT(r.rate_hz, 500.0);  // a sanity bound: timing figures are in bench-haptic
    EXPECT_LE(r.longest_stall_ms, kTimeoutMs);
    EXPECT_GT(r.longest_tick_gap_ms, 0.5);  // at least one period [ms]: the gap is measured
  }
  EXPECT_TRUE(quiet_session) << "the machine silenced the servo in every session:" << stalled;
}

TEST(OpenHaptics, AMissingLibHdIsAClearErrorThatPointsToTheSimulatedDevice) {
  try {
    drivers::OpenHapticsDevice device("/nonexistent/libHD.so");
    FAIL() << "a missing library was loaded";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/nonexistent/libHD.so"), std::string::npos) << what;
    EXPECT_NE(what.find("--device sim"), std::string::npos) << what;
  }
}

TEST(OpenHaptics, ALibraryWithoutTheHdApiIsRefusedNamingTheMissingSymbol) {
  try {
    drivers::OpenHapticsDevice device("libm.so.6");
    FAIL() << "libm was taken for libHD";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("hdInitDevice"), std::string::npos) << e.what();
  }
}

struct FakeHd {
  void* handle = dlopen(RIG_FAKE_LIBHD, RTLD_NOW | RTLD_LOCAL);
  ~FakeHd() {
    if (handle != nullptr) dlclose(handle);
  }
  template <typename F>
  F symbol(const char* name) const {
    return reinterpret_cast<F>(dlsym(handle, name));
  }
};

// The stand-in libHD opened as a Phantom, and the paper's model at 15 mmHg to feel through it
// (the device's constructor names the library if it cannot be loaded).
struct FakePhantom {
  FakeHd fake;
  drivers::OpenHapticsDevice device{RIG_FAKE_LIBHD};
  const model::ForceModel model = model::ForceModel::paper_interpreted();
  ModelForceSource source{model, 15.0};
};

TEST(OpenHaptics, TheServoRunsInTheSchedulerCallbackWithTheLimitsTheDeviceReports) {
  FakePhantom phantom;
  auto& [fake, device, model, source] = phantom;
  EXPECT_DOUBLE_EQ(device.limits().max_continuous_force_N, 0.6);
  EXPECT_DOUBLE_EQ(device.limits().max_stiffness_N_per_mm, 0.9);
  ServoSettings servo;
  servo.surface_mm =
      drivers::Vec3{0.0, 0.0, 0.0};  // the fake stylus reaches it 1.5 s after the first frame
  // Not a watchdog test (TheWatchdogTurnsForceOff… is): 500 ms, so a loaded machine's stall of
  // the fake scheduler thread cannot end the session.
  HapticSession session(device, source, servo, std::chrono::milliseconds(500));
  // [s] 1 mm deep 2 s after the first frame, with room for a late first frame
  const SessionReport report = session.run(nullptr, nullptr, 3.0);
  EXPECT_TRUE(report.fault.empty()) << report.fault;
  // Every servo tick is one device frame of the scheduler's callback. How many there were in
  // 3 s is a rate, measured in bench-haptic: under busy-machine an ASan build made 1,093.
  const long frames = fake.symbol<long (*)()>("fake_hd_frames")();
  EXPECT_GT(frames, 100);
  EXPECT_NEAR(static_cast<double>(report.ticks), static_cast<double>(frames), 1.0);
  EXPECT_DOUBLE_EQ(report.force_limit_N, 0.6);
  // 1 mm deep (after 2 s, the ramp-in long over): the model's toe and pre-cut, pushing the
  // stylus back out (+z). The mean over the frames 0.9-1.1 mm deep (~100 at 2 mm/s).
  const double at_1mm = fake.symbol<double (*)()>("fake_hd_force_at_1mm")();
  const double depth_mm = fake.symbol<double (*)()>("fake_hd_depth_at_1mm")();
  EXPECT_GT(fake.symbol<long (*)()>("fake_hd_frames_at_1mm")(), 10);  // ~100 at the full rate
  EXPECT_NEAR(depth_mm, 1.0, 0.05);
  EXPECT_NEAR(at_1mm, model.baseline(depth_mm, 15.0), 0.01);
  EXPECT_GT(at_1mm, 0.0);
  // Stopping the session turns the force off.
  EXPECT_EQ(fake.symbol<double (*)()>("fake_hd_last_force_z")(), 0.0);
}

TEST(OpenHaptics, AWarmMotorsErrorTurnsForceOffAndEndsTheSessionWithAClearFault) {
  FakePhantom phantom;
  auto& [fake, device, model, source] = phantom;
  // The subject is the device's error, not timing: a stall watchdog of 2 s (20 ms by default)
  // keeps a loaded machine's stall of the servo thread from ending the session first.
  HapticSession session(device, source, ServoSettings{}, std::chrono::milliseconds(2000));
  std::thread injector([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    fake.symbol<void (*)(unsigned)>("fake_hd_inject_error")(drivers::hd::kWarmMotors);
  });
  const SessionReport report = session.run(nullptr, nullptr, 5.0);
  injector.join();
  EXPECT_NE(report.fault.find("HD_WARM_MOTORS"), std::string::npos) << report.fault;
  EXPECT_LT(report.wall_s, 2.0);
  EXPECT_EQ(fake.symbol<int (*)()>("fake_hd_force_output_enabled")(), 0);
  EXPECT_EQ(fake.symbol<double (*)()>("fake_hd_last_force_z")(), 0.0);
}

TEST(OpenHaptics, AStalledServoHasTheDevicesForceOutputTurnedOffWhileItIsStillStalled) {
  FakePhantom phantom;
  auto& [fake, device, model, source] = phantom;
  // A watchdog of 250 ms (20 ms by default): a loaded machine's own stall of the servo thread
  // (CI builds beside this test) must not end the session before the injected one. The subject
  // is when the force goes off, which the longer timeout does not change.
  HapticSession session(device, source, ServoSettings{}, std::chrono::milliseconds(250));
  const auto force_output_enabled = fake.symbol<int (*)()>("fake_hd_force_output_enabled");
  int enabled_before = -1, enabled_during = -1;
  std::thread injector([&] {
    // The session turns force output on as it starts; wait for that (at most 5 s), not a guess.
    for (int waited_ms = 0; waited_ms < 5000 && force_output_enabled() != 1; waited_ms += 10)
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    enabled_before = force_output_enabled();
    fake.symbol<void (*)(long)>("fake_hd_stall_scheduler")(
        3000);  // the servo thread stands still 3 s
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));  // 6x the watchdog, still stalled
    enabled_during = force_output_enabled();
  });
  const SessionReport report = session.run(nullptr, nullptr, 10.0);
  injector.join();
  EXPECT_EQ(enabled_before, 1);
  EXPECT_EQ(enabled_during, 0)
      << "force output must go off while the servo is stalled, not when it comes back";
  EXPECT_TRUE(report.watchdog_tripped);
  EXPECT_NE(report.fault.find("servo stalled"), std::string::npos) << report.fault;
}

TEST(OpenHaptics, ADeviceThatFailsToInitialiseIsAClearError) {
  FakeHd fake;
  ASSERT_NE(fake.handle, nullptr) << dlerror();
  fake.symbol<void (*)(unsigned)>("fake_hd_fail_init")(drivers::hd::kCommError);
  try {
    drivers::OpenHapticsDevice device(RIG_FAKE_LIBHD);
    FAIL() << "initialised";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("cannot initialise"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::haptic
