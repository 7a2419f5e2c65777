// The fault-injection matrix (docs/faults.md): rigd against rig-sim over Modbus TCP, one
// fault per test, injected mid-cut through the simulator's test panel (or by acting on
// rigd's process). For each: the motor is off (the loop's own sample of the fault cycle
// already commands 0 V, and the simulated rig reports motor power off), the state is
// Fault or EStop with the reason in words, the run is archived with its samples up to the
// fault and its outcome, and nothing moves again before an explicit reset.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <thread>

#include "fault_matrix_fixture.hpp"

namespace rig::fault_matrix {
namespace {

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
  inject_and_check([](auto& p) { set(p, panel_reg::kLateReplyUs, kLate_us); }, "Fault",
                   "DAQ link lost", [](auto& p) { set(p, panel_reg::kLateReplyUs, 0); },
                   kDaqWatchdogBound_ms + kLate_us * 1e-3);
}

TEST_F(FaultMatrix, DaqAnswersGarbage) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kGarbageReplies, 1); }, "Fault", "DAQ link lost",
                   [](auto& p) { set(p, panel_reg::kGarbageReplies, 0); }, kDaqWatchdogBound_ms);
}

TEST_F(FaultMatrix, ForceSensorStuckWhileTheBladeMoves) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kStuckForce, 1); }, "Fault",
                   "force sensor stuck", [](auto& p) { set(p, panel_reg::kStuckForce, 0); },
                   50.0 + 20.0);
}

TEST_F(FaultMatrix, ForceOverload) {
  cut_into_tissue();
  inject_and_check([](auto& p) { p.set_float(panel_reg::kExtraForceN, 5.0F); }, "Fault",
                   "force limit exceeded",
                   [](auto& p) { p.set_float(panel_reg::kExtraForceN, 0.0F); }, kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EstopPressedMidCut) {
  cut_into_tissue();
  // The button is released again before the reset: a pressed one refuses reset (own test).
  inject_and_check([](auto& p) { set(p, panel_reg::kEstopButton, 1); }, "EStop",
                   "e-stop button pressed", [](auto& p) { set(p, panel_reg::kEstopButton, 0); },
                   kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EndLimitSwitchHit) {
  cut_into_tissue();
  inject_and_check([](auto& p) { set(p, panel_reg::kEndLimitForced, 1); }, "Fault",
                   "end limit switch", [](auto& p) { set(p, panel_reg::kEndLimitForced, 0); },
                   kSameCycleBound_ms);
}

TEST_F(FaultMatrix, EstopCommandedMidCut) {
  cut_into_tissue();
  // POST /api/estop (as `rig estop`): the API's thread (normal priority) queues the command and
  // the loop takes it in its next cycle. The bound is the same-cycle one plus the request's
  // way through the API, which a busy machine may hold up: 20 ms.
  inject_and_check([this](auto&) { rig_->api().post("/api/estop"); }, "EStop", "e-stop commanded",
                   [](auto&) {}, kSameCycleBound_ms + 17.0);
}

TEST_F(FaultMatrix, HomeLimitSwitchClosedMidCut) {
  cut_into_tissue();
  // The home switch reads closed 23 mm from home (a shorted switch or cable): outside homing a
  // fault.
  inject_and_check([](auto& p) { set(p, panel_reg::kHomeLimitForced, 1); }, "Fault",
                   "home limit switch", [](auto& p) { set(p, panel_reg::kHomeLimitForced, 0); },
                   kSameCycleBound_ms);
}

TEST_F(FaultMatrix, DaqRefusesOutputWrites) {
  cut_into_tissue();
  // Reads are answered, writes to the output block get Modbus exception 4: rigd cannot command
  // the motor any more. It faults after two refused writes; the DAQ's watchdog stops the motor.
  inject_and_check([](auto& p) { set(p, panel_reg::kRejectWrites, 1); }, "Fault",
                   "DAQ write failed", [](auto& p) { set(p, panel_reg::kRejectWrites, 0); },
                   kDaqWatchdogBound_ms);
}

TEST_F(FaultMatrix, DaqWatchdogTripsMidCut) {
  cut_into_tissue();
  // The DAQ drops its outputs on its own: rigd must not switch the motor on again.
  inject_and_check([](auto& p) { set(p, panel_reg::kTripWatchdog, 1); }, "Fault",
                   "DAQ watchdog tripped", [](auto& p) { set(p, panel_reg::kTripWatchdog, 0); },
                   kDaqSwitchedOffBound_ms);
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
  inject_and_check([](auto& p) { p.set_float(panel_reg::kPositionOffsetMm, 30.0F); }, "Fault",
                   "soft travel limit",
                   [](auto& p) { p.set_float(panel_reg::kPositionOffsetMm, 0.0F); },
                   kSameCycleBound_ms);
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
  const rt::IopSettings iop;  // rigd's defaults: config/rigd.sim.toml and the matrix set no band
  const sim::IopLineParams line;  // rig-sim's IOP line
  const double band_edge = iop_mmHg - iop.fault_band_mmHg;
  const auto leaves_band_ms = [&](double from_mmHg, double towards_mmHg) {
    return 1e3 * line.time_constant_s *
           std::log((from_mmHg - towards_mmHg) / (band_edge - towards_mmHg));
  };
  constexpr double kSlack_ms = 25.0;
  const double fastest_ms = leaves_band_ms(iop_mmHg - iop.settle_band_mmHg, 0.0);
  const double slowest_ms =
      leaves_band_ms(iop_mmHg + iop.settle_band_mmHg, line.pump_max_mmHg * (1.0 - leak_fraction));
  return {fastest_ms + iop.fault_after_ms - kSlack_ms, slowest_ms + iop.fault_after_ms + kSlack_ms};
}

TEST_F(FaultMatrix, IopLineLeaksMidCut) {
  cut_into_tissue();
  // A burst line: the pump can hold only 10 % of its pressure (4 mmHg at full command), far
  // below the run's 15 mmHg - 5. Bounds 268 ms and 442 ms after the injection.
  constexpr float kLeak = 0.9F;
  const LatencyWindow window = iop_leak_fault_window(15.0, kLeak);
  const Outcome out = inject_and_check(
      [](auto& p) { p.set_float(panel_reg::kIopLeak, kLeak); }, "Fault", "IOP out of range",
      [](auto& p) { p.set_float(panel_reg::kIopLeak, 0.0F); }, window.latest_ms);
  EXPECT_GE(out.motor_off_after_ms, window.earliest_ms)
      << "iop.fault_after_ms must pass first: a pump step is not a leak";
}

TEST_F(FaultMatrix, CarriageJammedMidCut) {
  cut_into_tissue();
  // The screw seizes; the reference runs on at 2 mm/s: safety.max_following_error_mm (1 mm) in 0.5
  // s.
  inject_and_check([](auto& p) { set(p, panel_reg::kCarriageJammed, 1); }, "Fault",
                   "following error", [](auto& p) { set(p, panel_reg::kCarriageJammed, 0); },
                   500.0 + 100.0);
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
      if (panel.input_float(proto::daq::sim_truth::kCarriageMm) <= -0.999)
        stopped_at = panel.sim_time_s();
    }
    std::this_thread::sleep_for(std::chrono::microseconds(500));
  }
  ASSERT_GE(stopped_at, 0.0) << "the carriage never reached its hard stop";
  EXPECT_TRUE(rig_->wait_state("Fault", 10)) << rig_->status().dump();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  EXPECT_FALSE(panel.motor_powered());
  const double off_ms = (panel.motor_off_time_s() - stopped_at) * 1e3;
  // 1 mm of following error at motion.homing_velocity_mm_s: 125 ms at 8 mm/s.
  EXPECT_LE(off_ms, 1000.0 / kHomingVelocity_mm_s + 70.0)
      << "motor-off latency after the carriage stopped";
  const std::string reason = rig_->status()["fault"];
  EXPECT_NE(reason.find("homing failed"), std::string::npos) << reason;
  EXPECT_EQ(rig_->status()["homed"], false);
  set(panel, panel_reg::kHomeSwitchBroken, 0);
  expect_reset_required("Fault");
  std::printf(
      "FAULT-TABLE | HomeSwitchBrokenWhileHoming | Fault: %s | motor off %.1f ms after the "
      "carriage stopped (sim time)\n",
      reason.c_str(), off_ms);
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
  std::printf(
      "FAULT-TABLE | RigdKilledWithSigkillMidRun | restarted Idle, not homed; run interrupted | "
      "motor off %.1f ms after the kill (DAQ watchdog)\n",
      off_ms);
}

}  // namespace
}  // namespace rig::fault_matrix
