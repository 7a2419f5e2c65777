// The fault matrix's rows that set up their own rig (docs/faults.md): a loop overrun storm, a
// lost camera, a full disk and an IOP line that leaks before the cut. The fixture and what every
// fault must give are in fault_matrix_fixture.hpp.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "fault_matrix_fixture.hpp"

namespace rig::fault_matrix {
namespace {

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
  const Outcome out = inject_and_check([&](auto&) { storm.start(pid, loop_thread); }, "Fault",
                                       "loop overrun storm", [&](auto&) { storm.stop(); },
                                       // The outer bound: the injection's 1000 stops, ~5 s.
                                       6000.0);
  storm.stop();
  // 500 of the last 1000 deadlines missed (safety.overrun_storm_*): ~625 ms at the asked duty
  // (661.6 ms measured, ASan, 2026-11-27). Counting each stop as its length less one period,
  // rigd must have judged the storm once the stops it suffered met that rule, within 100 ms
  // (a cycle after the last stop, and the motor's power-off on the DAQ).
  const rt::SafetySettings rule;
  const double met_ms = storm.rule_met_after_ms(rule.overrun_storm_missed_cycles,
                                                rule.overrun_storm_window_cycles, 1.0);
  std::printf(
      "STORM | %s | the stops met the rule %.1f ms after the injection, the motor was off after "
      "%.1f ms\n",
      storm.summary().c_str(), met_ms, out.motor_off_after_ms);
  // The machine's own late cycles count too, so rigd may judge it before the stops alone met
  // the rule (met_ms < 0 when they never did before the injection ended): never after.
  if (met_ms > 0.0) {
    EXPECT_LE(out.motor_off_after_ms, met_ms + 100.0)
        << "rigd judged the storm late: " << storm.summary();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
}

TEST_F(FaultMatrixCustomRig, CameraLostMidCut) {
  // A real GigE Vision camera (Aravis's fake one on loopback), its process killed mid-cut.
  auto camera = std::make_unique<cli::ChildProcess>(
      std::vector<std::string>{"/usr/bin/arv-fake-gv-camera-0.8", "-i", "127.0.0.1"},
      dir_.file("camera.log"));
  // The fake camera answers once it is up, which a busy machine delays: ask until it does.
  for (int attempt = 0; !rig_; ++attempt) {
    try {
      rig_ = std::make_unique<RigProcesses>(
          dir_, std::vector<std::string>{},
          quick_setup({"camera.kind=\"aravis\"", "camera.id=\"127.0.0.1\"", "camera.width=320",
                       "camera.height=240", "camera.frame_rate_hz=20"}));
    } catch (const std::exception& e) {
      if (attempt >= 10 ||
          std::string(e.what()).find("Can't connect to device") == std::string::npos)
        throw;
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
    }
  }
  cut_into_tissue();
  inject_and_check([&](auto&) { camera.reset(); }, "Fault", "camera lost", [](auto&) {},
                   1000.0 + 100.0);
}

// Lowers rigd's file size limit (RLIMIT_FSIZE, soft) on the running process; returns the old one.
rlimit limit_file_size(pid_t pid, rlim_t bytes) {
  rlimit old{};
  if (::prlimit(pid, RLIMIT_FSIZE, nullptr, &old) != 0)
    throw std::runtime_error("prlimit: cannot read rigd's limit");
  rlimit lowered = old;
  lowered.rlim_cur = bytes;
  if (::prlimit(pid, RLIMIT_FSIZE, &lowered, nullptr) != 0)
    throw std::runtime_error("prlimit: cannot lower rigd's limit");
  return old;
}

TEST_F(FaultMatrixCustomRig, DiskFullMidCut) {
  // Frames off: the frame file's writes would fail as well, and this row is the archive's.
  rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{},
                                        quick_setup({"camera.record_frames=false"}));
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
  EXPECT_GT(store.load_run(runs.back().id).size(), 500U)
      << "samples committed before the disk filled";
  archive::Database db(rig_->archive_path(), true);
  auto indices =
      db.prepare("SELECT MAX(idx) - MIN(idx) + 1, COUNT(*) FROM samples WHERE run_id = ?");
  indices.bind(1, runs.back().id);
  ASSERT_TRUE(indices.step());
  EXPECT_EQ(indices.integer(0), indices.integer(1)) << "a gap in the committed sample indices";
  // A new run is refused: 507 when the archive cannot take its row, 409 if the state is judged
  // first.
  expect_reset_required("Fault", 507, 409);
  ::prlimit(pid, RLIMIT_FSIZE, &old, nullptr);  // space again: rigd can log and stop cleanly
  std::printf(
      "FAULT-TABLE | DiskFullMidCut | Fault: %s | motor off %.1f ms after injection (sim time)\n",
      reason.c_str(), off_ms);
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
    std::printf("ACCIDENTAL | a timing fault while armed, reset and armed again: %s\n",
                fault.c_str());
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
  rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{},
                                        quick_setup({"iop.settle_timeout_s=2"}));
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
  auto times = db.prepare(
      "SELECT (SELECT MIN(t_s) FROM events WHERE run_id = ?1 AND kind = 'command' AND message = "
      "'arm: accepted'),"
      " (SELECT t_s FROM events WHERE run_id = ?1 AND kind = 'fault' AND message LIKE 'IOP did not "
      "settle%')");
  times.bind(1, newest_run(runs)["run_id"].get<std::int64_t>());
  ASSERT_TRUE(times.step());
  ASSERT_FALSE(times.is_null(0) || times.is_null(1))
      << "no arm or no 'IOP did not settle' event archived";
  const double fault_after_s = times.real(1) - times.real(0);
  EXPECT_GE(fault_after_s, kSettleTimeout_s - 0.001) << "faulted before iop.settle_timeout_s";
  // The loop counts a late cycle as at most 10 periods (control_loop.cpp): on a busy machine
  // the time-out comes later by the loop's longer stalls (76 ms seen at load average 11).
  EXPECT_LE(fault_after_s, kSettleTimeout_s + 0.25) << "faulted late after arming [s]";
  expect_reset_required("Fault");
  std::printf(
      "FAULT-TABLE | IopLeakBeforeTheCutNeverSettles | Fault: %s | motor never powered; fault %.4f "
      "s after arming (loop time)\n",
      reason.c_str(), fault_after_s);
}

}  // namespace
}  // namespace rig::fault_matrix
