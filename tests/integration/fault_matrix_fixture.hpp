// The fault matrix's fixture (docs/faults.md): rigd against rig-sim over Modbus TCP, a cut
// into the tissue, one injection and what every fault must give. Used by fault_matrix_test.cpp
// (faults on the default rig) and fault_matrix_custom_rig_test.cpp (rigs set up per row).
#pragma once

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <nlohmann/json.hpp>

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

namespace rig::fault_matrix {

using nlohmann::json;
using testing::RigProcesses;
using testing::ScratchDir;
namespace panel_reg = proto::daq::sim_panel;

inline const std::string kRun =
    R"({"eye_id":"FAULT","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14})";

// The newest run of GET /api/runs (ordered by id): a timing fault retried by the harness
// before the injection leaves its own faulted run before the one under test.
inline const json& newest_run(const json& runs) {
  return runs["runs"].back();
}

struct Outcome {
  double motor_off_after_ms = 0;  // sim time from injection to motor power off
  std::string state, reason;
};

// Homing at 8 mm/s instead of 4 and the IOP settled after 0.3 s instead of 1 s: each row
// reaches the tissue ~4 s sooner (the matrix runs in the ASan tier); nothing a row measures
// depends on either.
inline constexpr double kHomingVelocity_mm_s = 8.0;
inline std::vector<std::string> quick_setup(std::vector<std::string> sets = {}) {
  sets.push_back("motion.homing_velocity_mm_s=" + std::to_string(kHomingVelocity_mm_s));
  sets.push_back("iop.settle_time_s=0.3");
  return sets;
}

class FaultMatrix : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!custom_rig_)
      rig_ = std::make_unique<RigProcesses>(dir_, std::vector<std::string>{}, quick_setup());
  }
  bool custom_rig_ = false;
  std::int64_t cut_run_id_ = 0;  // the run cut_into_tissue() started (after any retries)

  // Starts a cut and waits until the blade is in the tissue. A timing fault of the simulated
  // rig on a busy machine before that (an overrun storm, a lost link) is printed, reset and the
  // cut started again by the harness: no row is about the machine's load.
  void cut_into_tissue() {
    std::string why;
    const auto in_tissue = [](const json& s) {
      return s["state"] == "Cutting" && s["position_mm"] > 23.0;
    };
    cut_run_id_ = rig_->cut_until(kRun, in_tissue, why);
    ASSERT_NE(cut_run_id_, 0) << why;
    testing::SimPanel panel(rig_->sim_port());
    ASSERT_TRUE(panel.motor_powered());
  }

  // Injects, waits for the stop and checks what every fault must give.
  // max_off_ms: the bound on motor-off latency for this fault (sim time from the injection).
  Outcome inject_and_check(const std::function<void(testing::SimPanel&)>& inject,
                           const std::string& state, const std::string& reason,
                           const std::function<void(testing::SimPanel&)>& clear,
                           double max_off_ms) {
    Outcome out;
    testing::SimPanel panel(rig_->sim_port());
    double injected_at = 0.0;
    {
      const testing::ScopedRealtime one_step;  // read the DAQ's time and inject, undisturbed
      injected_at = panel.sim_time_s();
      inject(panel);
    }
    EXPECT_TRUE(rig_->wait([&](const json& s) { return s["state"] == state; }, 15))
        << rig_->status().dump();
    std::this_thread::sleep_for(std::chrono::milliseconds(300));
    testing::SimPanel after(
        rig_->sim_port());  // a dropped link closes the first panel's connection
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
                ::testing::UnitTest::GetInstance()->current_test_info()->name(), out.state.c_str(),
                out.reason.c_str(), out.motor_off_after_ms);
    return out;
  }

  void expect_run_archived_up_to_the_fault(const std::string& reason) {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    const json runs = json::parse(rig_->api().get("/api/runs").body);
    ASSERT_FALSE(runs["runs"].empty());
    const json& run = newest_run(runs);
    EXPECT_EQ(run.value("run_id", std::int64_t{0}), cut_run_id_)
        << "the run the row cut is the newest";
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
    auto last = db.prepare(
        "SELECT t_s, motor_V, idx - (SELECT MIN(idx) FROM samples WHERE run_id = ?1) + 1,"
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
  void expect_reset_required(const std::string& state, int refused_with = 409,
                             int also_refused_with = 409) {
    const auto run = rig_->api().post("/api/run", kRun);
    EXPECT_TRUE(run.status == refused_with || run.status == also_refused_with)
        << "a run started without a reset (" << run.status << "): " << run.body;
    EXPECT_EQ(rig_->api().post("/api/home").status, 409) << "homing started without a reset";
    EXPECT_EQ(rig_->status()["state"], state);
    const auto reset = rig_->api().post("/api/reset");
    EXPECT_EQ(reset.status, 200) << reset.body;
    EXPECT_TRUE(rig_->wait([](const json& s) { return s["state"] == "Idle"; }, 10))
        << rig_->status().dump();
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

class FaultMatrixCustomRig : public FaultMatrix {
 protected:
  FaultMatrixCustomRig() { custom_rig_ = true; }
};

}  // namespace rig::fault_matrix
