// The fault-injection matrix (docs/faults.md): rigd against rig-sim over Modbus TCP, one
// fault per test, injected mid-cut through the simulator's test panel (or by acting on
// rigd's process). For each: the motor is off (the loop's own sample of the fault cycle
// already commands 0 V, and the simulated rig reports motor power off), the state is
// Fault or EStop with the reason in words, the run is archived with its samples up to the
// fault and its outcome, and nothing moves again before an explicit reset.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <thread>

#include "archive.hpp"
#include "loop_settings.hpp"
#include "overrun_storm_injector.hpp"
#include "rig/sim/physics_params.hpp"
#include "rig_processes.hpp"
#include "scoped_realtime.hpp"
#include "sim_panel.hpp"
#include "sqlite_handle.hpp"

namespace rig {
namespace {

using nlohmann::json;
using testing::RigProcesses;
using testing::ScratchDir;
namespace panel_reg = proto::daq::sim_panel;

const std::string kRun = R"({"eye_id":"FAULT","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14})";

// The newest run of GET /api/runs (ordered by id): a timing fault retried by the harness
// before the injection leaves its own faulted run before the one under test.
const json& newest_run(const json& runs) { return runs["runs"].back(); }

struct Outcome {
  double motor_off_after_ms = 0;  // sim time from injection to motor power off
  std::string state, reason;
};

// Homing at 8 mm/s instead of 4 and the IOP settled after 0.3 s instead of 1 s: each row
// reaches the tissue ~4 s sooner (the matrix runs in the ASan tier); nothing a row measures
// depends on either.
constexpr double kHomingVelocity_mm_s = 8.0;
std::vector<std::string> quick_setup(std::vector<std::string> sets = {}) {
  sets.push_back("motion.homing_velocity_mm_s=" + std::to_string(kHomingVelocity_mm_s));
  sets.push_back("iop.settle_time_s=0.3");
  return sets;
}

class FaultMatrix : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!custom_rig_) rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{}, quick_setup());
  }
  bool custom_rig_ = false;
  std::int64_t cut_run_id_ = 0;  // the run cut_into_tissue() started (after any retries)

  // Starts a cut and waits until the blade is in the tissue. A timing fault of the simulated
  // rig on a busy machine before that (an overrun storm, a lost link) is printed, reset and the
  // cut started again by the harness: no row is about the machine's load.
  void cut_into_tissue() {
    std::string why;
    const auto in_tissue = [](const json& s) { return s["state"] == "Cutting" && s["position_mm"] > 23.0; };
    cut_run_id_ = rig_->cut_until(kRun, in_tissue, why);
    ASSERT_NE(cut_run_id_, 0) << why;
    testing::SimPanel panel(rig_->sim_port());
    ASSERT_TRUE(panel.motor_powered());
  }

  // Injects, waits for the stop and checks what every fault must give.
  // max_off_ms: the bound on motor-off latency for this fault (sim time from the injection).
  Outcome inject_and_check(const std::function<void(testing::SimPanel&)>& inject, const std::string& state,
                           const std::string& reason, const std::function<void(testing::SimPanel&)>& clear,
                           double max_off_ms) {
    Outcome out;
    testing::SimPanel panel(rig_->sim_port());
    double injected_at = 0.0;
    {
      const testing::ScopedRealtime one_step;  // read the DAQ's time and inject, undisturbed
      injected_at = panel.sim_time_s();
      inject(panel);
    }
    EXPECT_TRUE(rig_->wait([&](const json& s) { return s["state"] == state; }, 15)) << rig_->status().dump();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    testing::SimPanel after(rig_->sim_port());  // a dropped link closes the first panel's connection
    EXPECT_FALSE(after.motor_powered()) << "motor still powered";
    out.motor_off_after_ms = (after.motor_off_time_s() - injected_at) * 1e3;
    // The last power-off counts: a motor switched on again after the fault shows up as late.
    EXPECT_GE(out.motor_off_after_ms, -0.1) << "the motor was off before the injection";
    EXPECT_LE(out.motor_off_after_ms, max_off_ms) << "motor-off latency";
    const json status = rig_->status();
    out.state = status.value("state", std::string{});
    const json fault = status.value("fault", json{});
    out.reason = fault.is_string() ? fault.get<std::string>() : std::string{};
    EXPECT_FALSE(reason.empty()) << "every row names its own reason";
    EXPECT_NE(out.reason.find(reason), std::string::npos) << out.reason;
    clear(after);
    expect_run_archived_up_to_the_fault(reason);
    expect_reset_required(state);
    std::printf("FAULT-TABLE | %s | %s: %s | motor off %.1f ms after injection (sim time)\n",
                ::testing::UnitTest::GetInstance()->current_test_info()->name(), out.state.c_str(), out.reason.c_str(),
                out.motor_off_after_ms);
    return out;
  }

  void expect_run_archived_up_to_the_fault(const std::string& reason) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const json runs = json::parse(rig_->api().get("/api/runs").body);
    ASSERT_FALSE(runs["runs"].empty());
    const json& run = newest_run(runs);
    EXPECT_EQ(run.value("run_id", std::int64_t{0}), cut_run_id_) << "the run the row cut is the newest";
    EXPECT_EQ(run.value("outcome", std::string{}), "fault");
    // value(): a run that ended otherwise (no reason key) fails here instead of aborting.
    EXPECT_NE(run.value("reason", std::string{}).find(reason), std::string::npos) << run.dump();
    EXPECT_GT(run.value("samples", 0), 1000) << "samples up to the fault";
    archive::Database db(rig_->archive_path(), true);
    const std::int64_t id = run.value("run_id", std::int64_t{-1});
    auto fault = db.prepare("SELECT t_s, message FROM events WHERE run_id = ? AND kind = 'fault'");
    fault.bind(1, id);
    ASSERT_TRUE(fault.step()) << "no fault event archived";
    EXPECT_NE(fault.text(1).find(reason), std::string::npos) << fault.text(1);
    // Every sample up to the fault cycle is there: the run's last sample is the fault cycle's
    // own (same loop time as the fault event, its motor command 0 V), its indices (the loop's
    // cycle numbers) have no gap. Exact: a late loop under load moves no boundary.
    auto last = db.prepare("SELECT t_s, motor_V, idx - (SELECT MIN(idx) FROM samples WHERE run_id = ?1) + 1,"
                           " (SELECT COUNT(*) FROM samples WHERE run_id = ?1) FROM samples WHERE run_id = ?1"
                           " ORDER BY idx DESC LIMIT 1");
    last.bind(1, id);
    ASSERT_TRUE(last.step());
    EXPECT_EQ(last.real(0), fault.real(0)) << "the run's last sample is not the fault cycle's";
    EXPECT_EQ(last.real(1), 0.0) << "the fault cycle commands 0 V";
    EXPECT_EQ(last.integer(2), last.integer(3)) << "a gap in the sample indices";
  }

  // refused_with: 409 (wrong state); also_refused_with: another refusal that is right too
  // (507 when the archive cannot take a new run either: whether the full disk still holds
  // one more run row depends on where the last commit failed).
  void expect_reset_required(const std::string& state, int refused_with = 409, int also_refused_with = 409) {
    const auto run = rig_->api().post("/api/run", kRun);
    EXPECT_TRUE(run.status == refused_with || run.status == also_refused_with)
        << "a run started without a reset (" << run.status << "): " << run.body;
    EXPECT_EQ(rig_->api().post("/api/home").status, 409) << "homing started without a reset";
    EXPECT_EQ(rig_->status()["state"], state);
    const auto reset = rig_->api().post("/api/reset");
    EXPECT_EQ(reset.status, 200) << reset.body;
    EXPECT_TRUE(rig_->wait([](const json& s) { return s["state"] == "Idle"; }, 10)) << rig_->status().dump();
  }

  static void set(testing::SimPanel& p, int reg, std::uint16_t v) { p.set(reg, v); }

  // Bounds on motor-off latency [ms of sim time after the injection]. The DAQ's watchdog is
  // daq.watchdog_ms = 15 (config/rigd.sim.toml; 30 in sanitized trees, rig_processes.hpp)
  // after rigd's last write; the injection is dated up to ~1 ms late.
  static constexpr double kDaqWatchdog_ms = testing::kSimDaqWatchdog_ms;
  static constexpr double kDaqWatchdogBound_ms = kDaqWatchdog_ms + 2.0;
  static constexpr double kSameCycleBound_ms = 3.0;  // one 1 ms period, the DAQ round trip, slack
  static constexpr double kDaqSwitchedOffBound_ms = 2.0;  // the DAQ itself drops the outputs

  ScratchDir dir_{"fault-matrix"};
  std::unique_ptr<RigProcesses> rig_;
};

TEST_F(FaultMatrix, ModbusLinkDroppedMidCut) {
  cut_into_tissue();
  // 5: the link is cut for 50 ms, longer than the link-loss time (10 ms; 25 ms sanitized) and
  // the DAQ's watchdog; at 1 (10 ms) it was no longer than the link-loss time itself. It must
  // end on its own: the row reads the rig-sim's truth over the same link afterwards.
  inject_and_check([](auto& p) { set(p, panel_reg::kLinkDrop, 5); }, "Fault", "DAQ link lost",
                   [](auto& p) { set(p, panel_reg::kLinkDrop, 0); }, kDaqWatchdogBound_ms);
}

TEST_F(FaultMatrix, DaqAnswersTooLate) {
  cut_into_tissue();
  // A late DAQ still applies the write it received just after the injection, 3 ms late, and
  // that write feeds its watchdog: the bound is the watchdog counted from then (measured
  // 33.3 ms in an ASan tree on a busy machine, against the watchdog's 30 + 2).
  constexpr std::uint16_t kLate_us = 3000;
  inject_and_check([](auto& p) { set(p, panel_reg::kLateReplyUs, kLate_us); }, "Fault", "DAQ link lost",
                   [](auto& p) { set(p, panel_reg::kLateReplyUs, 0); }, kDaqWatchdogBound_ms + kLate_us * 1e-3);
}

TEST_F(FaultMatrix, DaqAnswersGarbage) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kGarbageReplies, 1); }, "Fault", "DAQ link lost",
                   [](auto& p) { set(p, panel_reg::kGarbageReplies, 0); }, kDaqWatchdogBound_ms);
}

TEST_F(FaultMatrix, ForceSensorStuckWhileTheBladeMoves) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kStuckForce, 1); }, "Fault", "force sensor stuck",
                   [](auto& p) { set(p, panel_reg::kStuckForce, 0); }, 50.0 + 20.0);
}

TEST_F(FaultMatrix, ForceOverload) {
  cut_into_tissue();
  inject_and_check([](auto& p) { p.set_float(panel_reg::kExtraForceN, 5.0F); }, "Fault", "force limit exceeded",
                   [](auto& p) { p.set_float(panel_reg::kExtraForceN, 0.0F); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EstopPressedMidCut) {
  cut_into_tissue();
  // The button is released again before the reset: a pressed one refuses reset (own test).
  inject_and_check([](auto& p) { set(p, panel_reg::kEstopButton, 1); }, "EStop", "e-stop button pressed",
                   [](auto& p) { set(p, panel_reg::kEstopButton, 0); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EndLimitSwitchHit) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kEndLimitForced, 1); }, "Fault", "end limit switch",
                   [](auto& p) { set(p, panel_reg::kEndLimitForced, 0); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EstopCommandedMidCut) {
  cut_into_tissue();
  // POST /api/estop (as `rig estop`): the API's thread (normal priority) queues the command and
  // the loop takes it in its next cycle. The bound is the same-cycle one plus the request's
  // way through the API, which a busy machine may hold up: 20 ms.
  inject_and_check([this](auto&) { rig_->api().post("/api/estop"); }, "EStop", "e-stop commanded", [](auto&) {},
                   kSameCycleBound_ms + 17.0);
}

TEST_F(FaultMatrix, HomeLimitSwitchClosedMidCut) {
  cut_into_tissue();
  // The home switch reads closed 23 mm from home (a shorted switch or cable): outside homing a fault.
  inject_and_check([](auto& p) { set(p, panel_reg::kHomeLimitForced, 1); }, "Fault", "home limit switch",
                   [](auto& p) { set(p, panel_reg::kHomeLimitForced, 0); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, DaqRefusesOutputWrites) {
  cut_into_tissue();
  // Reads are answered, writes to the output block get Modbus exception 4: rigd cannot command
  // the motor any more. It faults after two refused writes; the DAQ's watchdog stops the motor.
  inject_and_check([](auto& p) { set(p, panel_reg::kRejectWrites, 1); }, "Fault", "DAQ write failed",
                   [](auto& p) { set(p, panel_reg::kRejectWrites, 0); }, kDaqWatchdogBound_ms);
}

TEST_F(FaultMatrix, DaqWatchdogTripsMidCut) {
  cut_into_tissue();
  // The DAQ drops its outputs on its own: rigd must not switch the motor on again.
  inject_and_check([](auto& p) { set(p, panel_reg::kTripWatchdog, 1); }, "Fault", "DAQ watchdog tripped",
                   [](auto& p) { set(p, panel_reg::kTripWatchdog, 0); }, kDaqSwitchedOffBound_ms);
}

TEST_F(FaultMatrix, DaqRebootsMidCut) {
  cut_into_tissue();
  // Outputs off, watchdog off, conversion counter from 0: fresh-looking data that must not
  // be taken for the same DAQ carrying on.
  inject_and_check([](auto& p) { set(p, panel_reg::kRestartDaq, 1); }, "Fault", "DAQ restarted",
                   [](auto& p) { set(p, panel_reg::kRestartDaq, 0); }, kDaqSwitchedOffBound_ms);
}

TEST_F(FaultMatrix, MotorDriveFault) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kDriveFault, 1); }, "Fault", "motor drive fault",
                   [](auto& p) { set(p, panel_reg::kDriveFault, 0); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, PositionBeyondTheSoftLimit) {
  cut_into_tissue();
  // The potentiometer reads 30 mm further (slipped coupling): past motion.soft_max_mm (44 mm).
  inject_and_check([](auto& p) { p.set_float(panel_reg::kPositionOffsetMm, 30.0F); }, "Fault", "soft travel limit",
                   [](auto& p) { p.set_float(panel_reg::kPositionOffsetMm, 0.0F); }, kSameCycleBound_ms);
}

// When an IOP leak mid-cut must stop the motor [ms after the injection]. The pressure falls from
// the run's IOP (settled within iop.settle_band_mmHg) towards what the pump can still hold, 0
// (pump command 0) to pump_max x (1 - leak) (full command), with the line's time constant tau
// (rig-sim's first-order IOP line), so it leaves the band (IOP - iop.fault_band_mmHg) after
// tau ln((P0 - P_inf) / (P0 - band - P_inf)); rigd faults iop.fault_after_ms later. Slack: a
// noisy reading (0.05 mmHg) at the band edge restarts the count for a few cycles (the pressure
// falls >= 12 mmHg/s there), the injection is dated up to ~1 ms late, one period, the round trip.
struct LatencyWindow {
  double earliest_ms = 0, latest_ms = 0;
};
LatencyWindow iop_leak_fault_window(double iop_mmHg, double leak_fraction) {
  const rt::IopSettings iop;        // rigd's defaults: config/rigd.sim.toml and the matrix set no band
  const sim::IopLineParams line;    // rig-sim's IOP line
  const double band_edge = iop_mmHg - iop.fault_band_mmHg;
  const auto leaves_band_ms = [&](double from_mmHg, double towards_mmHg) {
    return 1e3 * line.time_constant_s * std::log((from_mmHg - towards_mmHg) / (band_edge - towards_mmHg));
  };
  constexpr double kSlack_ms = 25.0;
  const double fastest_ms = leaves_band_ms(iop_mmHg - iop.settle_band_mmHg, 0.0);
  const double slowest_ms = leaves_band_ms(iop_mmHg + iop.settle_band_mmHg, line.pump_max_mmHg * (1.0 - leak_fraction));
  return {fastest_ms + iop.fault_after_ms - kSlack_ms, slowest_ms + iop.fault_after_ms + kSlack_ms};
}

TEST_F(FaultMatrix, IopLineLeaksMidCut) {
  cut_into_tissue();
  // A burst line: the pump can hold only 10 % of its pressure (4 mmHg at full command), far
  // below the run's 15 mmHg - 5. Bounds 268 ms and 442 ms after the injection.
  constexpr float kLeak = 0.9F;
  const LatencyWindow window = iop_leak_fault_window(15.0, kLeak);
  const Outcome out = inject_and_check([](auto& p) { p.set_float(panel_reg::kIopLeak, kLeak); }, "Fault", "IOP out of range",
                                       [](auto& p) { p.set_float(panel_reg::kIopLeak, 0.0F); }, window.latest_ms);
  EXPECT_GE(out.motor_off_after_ms, window.earliest_ms) << "iop.fault_after_ms must pass first: a pump step is not a leak";
}

TEST_F(FaultMatrix, CarriageJammedMidCut) {
  cut_into_tissue();
  // The screw seizes; the reference runs on at 2 mm/s: safety.max_following_error_mm (1 mm) in 0.5 s.
  inject_and_check([](auto& p) { set(p, panel_reg::kCarriageJammed, 1); }, "Fault", "following error",
                   [](auto& p) { set(p, panel_reg::kCarriageJammed, 0); }, 500.0 + 100.0);
}

TEST_F(FaultMatrix, HomeSwitchBrokenWhileHoming) {
  testing::SimPanel panel(rig_->sim_port());
  set(panel, panel_reg::kHomeSwitchBroken, 1);
  ASSERT_EQ(rig_->api().post("/api/home").status, 200);
  // The carriage runs into its hard stop (-1 mm): the time it stops, read from the DAQ.
  double stopped_at = -1.0;
  for (int i = 0; i < 20000 && stopped_at < 0.0; ++i) {
    {
      const testing::ScopedRealtime one_step;  // position and time read together
      if (panel.input_float(proto::daq::sim_truth::kCarriageMm) <= -0.999) stopped_at = panel.sim_time_s();
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  ASSERT_GE(stopped_at, 0.0) << "the carriage never reached its hard stop";
  EXPECT_TRUE(rig_->wait_state("Fault", 10)) << rig_->status().dump();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(panel.motor_powered());
  const double off_ms = (panel.motor_off_time_s() - stopped_at) * 1e3;
  // 1 mm of following error at motion.homing_velocity_mm_s: 125 ms at 8 mm/s.
  EXPECT_LE(off_ms, 1000.0 / kHomingVelocity_mm_s + 70.0) << "motor-off latency after the carriage stopped";
  const std::string reason = rig_->status()["fault"];
  EXPECT_NE(reason.find("homing failed"), std::string::npos) << reason;
  EXPECT_EQ(rig_->status()["homed"], false);
  set(panel, panel_reg::kHomeSwitchBroken, 0);
  expect_reset_required("Fault");
  std::printf("FAULT-TABLE | HomeSwitchBrokenWhileHoming | Fault: %s | motor off %.1f ms after the carriage stopped (sim time)\n",
              reason.c_str(), off_ms);
}

class FaultMatrixCustomRig : public FaultMatrix {
 protected:
  FaultMatrixCustomRig() { custom_rig_ = true; }
};

TEST_F(FaultMatrixCustomRig, LoopOverrunStorm) {
  // The stops below (4 ms) are shorter than the DAQ's watchdog (15 ms): they show as rigd's
  // overrun storm, not as the DAQ dropping its outputs (its own row, DaqWatchdogTripsMidCut).
  rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{}, quick_setup());
  cut_into_tissue();
  // rigd's process stopped for 4 ms of every 5 ms (overrun_storm_injector.hpp): the loop
  // misses 4 deadlines of 5; the injecting thread runs above rigd's loop (SCHED_FIFO 90 when
  // allowed): on a busy machine a thread of normal priority slept 10 ms instead of 1 and the
  // storm never built up. Each stop is timed: the bound below is rigd's rule applied to them.
  testing::OverrunStormInjector storm;
  const pid_t pid = rig_->rigd().pid();
  const pid_t loop_thread = testing::OverrunStormInjector::thread_named(pid, "rigd-loop");
  ASSERT_NE(loop_thread, 0) << "rigd has no thread named rigd-loop";
  const Outcome out = inject_and_check([&](auto&) { storm.start(pid, loop_thread); }, "Fault", "loop overrun storm",
                                       [&](auto&) { storm.stop(); },
                                       // The outer bound: the injection's 1000 stops, ~5 s.
                                       6000.0);
  storm.stop();
  // 500 of the last 1000 deadlines missed (safety.overrun_storm_*): ~625 ms at the asked duty
  // (661.6 ms measured, ASan, 2026-11-27). Counting each stop as its length less one period,
  // rigd must have judged the storm once the stops it suffered met that rule, within 100 ms
  // (a cycle after the last stop, and the motor's power-off on the DAQ).
  const rt::SafetySettings rule;
  const double met_ms = storm.rule_met_after_ms(rule.overrun_storm_missed_cycles, rule.overrun_storm_window_cycles, 1.0);
  std::printf("STORM | %s | the stops met the rule %.1f ms after the injection, the motor was off after %.1f ms\n",
              storm.summary().c_str(), met_ms, out.motor_off_after_ms);
  // The machine's own late cycles count too, so rigd may judge it before the stops alone met
  // the rule (met_ms < 0 when they never did before the injection ended): never after.
  if (met_ms > 0.0) {
    EXPECT_LE(out.motor_off_after_ms, met_ms + 100.0) << "rigd judged the storm late: " << storm.summary();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

TEST_F(FaultMatrixCustomRig, CameraLostMidCut) {
  // A real GigE Vision camera (Aravis's fake one on loopback), its process killed mid-cut.
  auto camera = std::make_unique<cli::ChildProcess>(
      std::vector<std::string>{"/usr/bin/arv-fake-gv-camera-0.8", "-i", "127.0.0.1"}, dir_.file("camera.log"));
  // The fake camera answers once it is up, which a busy machine delays: ask until it does.
  for (int attempt = 0; !rig_; ++attempt) {
    try {
      rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{},
                                            quick_setup({"camera.kind=\"aravis\"", "camera.id=\"127.0.0.1\"",
                                                         "camera.width=320", "camera.height=240", "camera.frame_rate_hz=20"}));
    } catch (const std::exception& e) {
      if (attempt >= 10 || std::string(e.what()).find("Can't connect to device") == std::string::npos) throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
  cut_into_tissue();
  inject_and_check([&](auto&) { camera.reset(); }, "Fault", "camera lost", [](auto&) {}, 1000.0 + 100.0);
}

// Lowers rigd's file size limit (RLIMIT_FSIZE, soft) on the running process; returns the old one.
rlimit limit_file_size(pid_t pid, rlim_t bytes) {
  rlimit old{};
  if (::prlimit(pid, RLIMIT_FSIZE, nullptr, &old) != 0) throw std::runtime_error("prlimit: cannot read rigd's limit");
  rlimit lowered = old;
  lowered.rlim_cur = bytes;
  if (::prlimit(pid, RLIMIT_FSIZE, &lowered, nullptr) != 0) throw std::runtime_error("prlimit: cannot lower rigd's limit");
  return old;
}

TEST_F(FaultMatrixCustomRig, DiskFullMidCut) {
  // Frames off: the frame file's writes would fail as well, and this row is the archive's.
  rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{}, quick_setup({"camera.record_frames=false"}));
  cut_into_tissue();
  testing::SimPanel panel(rig_->sim_port());
  const pid_t pid = rig_->rigd().pid();
  double injected_at = 0.0;
  rlimit old{};
  {
    const testing::ScopedRealtime one_step;  // read the DAQ's time and fill the disk, undisturbed
    injected_at = panel.sim_time_s();
    // 1 byte: from now on every write of rigd to a file fails (EFBIG; rigd ignores SIGXFSZ),
    // as on a full disk: the recorder's next commit fails.
    old = limit_file_size(pid, 1);
  }
  EXPECT_TRUE(rig_->wait_state("Fault", 15)) << rig_->status().dump();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(panel.motor_powered());
  const double off_ms = (panel.motor_off_time_s() - injected_at) * 1e3;
  EXPECT_GE(off_ms, -0.1) << "the motor was off before the injection";
  // The recorder commits every archive.flush_interval_ms (50) and polls every 2 ms; the first
  // commit after the disk filled fails and the loop stops the motor in its next cycle. A
  // commit already syncing when the disk filled still succeeds, and the next one comes one
  // interval after it: two intervals cover that sync on a busy disk.
  constexpr double kFlushInterval_ms = 50.0;
  EXPECT_LE(off_ms, 2 * kFlushInterval_ms) << "motor-off latency";
  const std::string reason = rig_->status()["fault"];
  EXPECT_NE(reason.find("archive write failed"), std::string::npos) << reason;
  // What was committed before the disk filled is there, readable and without a gap.
  archive::Archive store(rig_->archive_path(), true);
  const auto runs = store.list_runs();
  ASSERT_FALSE(runs.empty());
  EXPECT_GT(store.load_run(runs.back().id).size(), 500U) << "samples committed before the disk filled";
  archive::Database db(rig_->archive_path(), true);
  auto indices = db.prepare("SELECT MAX(idx) - MIN(idx) + 1, COUNT(*) FROM samples WHERE run_id = ?");
  indices.bind(1, runs.back().id);
  ASSERT_TRUE(indices.step());
  EXPECT_EQ(indices.integer(0), indices.integer(1)) << "a gap in the committed sample indices";
  // A new run is refused: 507 when the archive cannot take its row, 409 if the state is judged first.
  expect_reset_required("Fault", 507, 409);
  ::prlimit(pid, RLIMIT_FSIZE, &old, nullptr);  // space again: rigd can log and stop cleanly
  std::printf("FAULT-TABLE | DiskFullMidCut | Fault: %s | motor off %.1f ms after injection (sim time)\n", reason.c_str(),
              off_ms);
}

// Arms a run against a leaking IOP line and waits for its fault; a timing fault of the simulated
// rig meanwhile (an overrun storm on a busy machine) is printed, reset and the run armed again,
// three times at most. Returns the sim time before the run was posted (-1 if it never faulted).
double arm_against_a_leak_until_fault(RigProcesses& rig, testing::SimPanel& panel) {
  for (int attempt = 0; attempt < 3; ++attempt) {
    std::string why;
    if (!rig.prepare(why)) {
      ADD_FAILURE() << why;
      return -1.0;
    }
    panel.set_float(panel_reg::kIopLeak, 0.9F);  // a burst line: 4 mmHg at most, the run asks 15
    const double before_run_s = panel.sim_time_s();
    if (rig.api().post("/api/run", kRun).status != 200 || !rig.wait_state("Fault", 15)) {
      ADD_FAILURE() << "the armed run did not fault: " << rig.status().dump();
      return -1.0;
    }
    const std::string fault = rig.status().value("fault", "");
    if (!cli::is_timing_fault(fault)) return before_run_s;
    std::printf("ACCIDENTAL | a timing fault while armed, reset and armed again: %s\n", fault.c_str());
    panel.set_float(panel_reg::kIopLeak, 0.0F);
    rig.api().post("/api/reset");
    rig.wait([](const json& st) { return st["interlocks"]["link_ok"] == true; }, 10);
  }
  ADD_FAILURE() << "three timing faults in a row";
  return -1.0;
}

TEST_F(FaultMatrixCustomRig, IopLeakBeforeTheCutNeverSettles) {
  // iop.settle_timeout_s = 2 instead of 20: the row waits 2 s for a pressure that cannot come.
  constexpr double kSettleTimeout_s = 2.0;
  rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{}, quick_setup({"iop.settle_timeout_s=2"}));
  testing::SimPanel panel(rig_->sim_port());
  const double before_run_s = arm_against_a_leak_until_fault(*rig_, panel);
  ASSERT_GE(before_run_s, 0.0);
  // The motor never ran: Armed keeps it off until the IOP has settled.
  EXPECT_FALSE(panel.motor_powered());
  EXPECT_LT(panel.motor_off_time_s(), before_run_s) << "the motor was powered while armed";
  const std::string reason = rig_->status()["fault"];
  EXPECT_NE(reason.find("IOP did not settle"), std::string::npos) << reason;
  panel.set_float(panel_reg::kIopLeak, 0.0F);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  // The run never started: archived as cancelled, with the fault event dated by rigd's loop
  // iop.settle_timeout_s after its arming.
  const json runs = json::parse(rig_->api().get("/api/runs").body);
  ASSERT_FALSE(runs["runs"].empty());
  EXPECT_EQ(newest_run(runs)["outcome"], "cancelled") << newest_run(runs).dump();
  EXPECT_EQ(newest_run(runs)["samples"], 0);
  archive::Database db(rig_->archive_path(), true);
  auto times = db.prepare("SELECT (SELECT MIN(t_s) FROM events WHERE run_id = ?1 AND kind = 'command' AND message = 'arm: accepted'),"
                          " (SELECT t_s FROM events WHERE run_id = ?1 AND kind = 'fault' AND message LIKE 'IOP did not settle%')");
  times.bind(1, newest_run(runs)["run_id"].get<std::int64_t>());
  ASSERT_TRUE(times.step());
  ASSERT_FALSE(times.is_null(0) || times.is_null(1)) << "no arm or no 'IOP did not settle' event archived";
  const double fault_after_s = times.real(1) - times.real(0);
  EXPECT_GE(fault_after_s, kSettleTimeout_s - 0.001) << "faulted before iop.settle_timeout_s";
  // The loop counts a late cycle as at most 10 periods (control_loop.cpp): on a busy machine
  // the time-out comes later by the loop's longer stalls (76 ms seen at load average 11).
  EXPECT_LE(fault_after_s, kSettleTimeout_s + 0.25) << "faulted late after arming [s]";
  expect_reset_required("Fault");
  std::printf("FAULT-TABLE | IopLeakBeforeTheCutNeverSettles | Fault: %s | motor never powered; fault %.4f s after arming (loop time)\n",
              reason.c_str(), fault_after_s);
}

TEST_F(FaultMatrix, RigdKilledWithSigkillMidRun) {
  cut_into_tissue();
  testing::SimPanel panel(rig_->sim_port());
  double killed_at = 0.0;
  {
    const testing::ScopedRealtime one_step;  // read the DAQ's time and kill, undisturbed
    killed_at = panel.sim_time_s();
    ::kill(rig_->rigd().pid(), SIGKILL);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  // Nobody is left to command the motor: the DAQ's own watchdog cuts it.
  EXPECT_FALSE(panel.motor_powered());
  const double off_ms = (panel.motor_off_time_s() - killed_at) * 1e3;
  EXPECT_LE(off_ms, kDaqWatchdog_ms + 1.0) << "DAQ watchdog";
  rig_->start_rigd();  // systemd's Restart=on-failure does this on the rig
  const json runs = json::parse(rig_->api().get("/api/runs").body);
  ASSERT_FALSE(runs["runs"].empty());
  EXPECT_EQ(newest_run(runs)["run_id"], cut_run_id_) << "the run killed is the newest";
  EXPECT_EQ(newest_run(runs)["outcome"], "interrupted");
  EXPECT_GT(newest_run(runs)["samples"].get<int>(), 1000) << "samples up to the kill are kept";
  // A restarted rigd is not homed: nothing moves before the technician homes it again.
  EXPECT_EQ(rig_->status()["homed"], false);
  EXPECT_EQ(rig_->api().post("/api/run", kRun).status, 409);
  std::printf("FAULT-TABLE | RigdKilledWithSigkillMidRun | restarted Idle, not homed; run interrupted | motor off %.1f ms after the kill (DAQ watchdog)\n",
              off_ms);
}

}  // namespace
}  // namespace rig
