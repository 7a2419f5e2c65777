// The Modbus DAQ driver against the simulated rig's real Modbus TCP server on loopback, and
// mbpoll (an independent client) reading the same server.
#include <gtest/gtest.h>
#include <pthread.h>
#include <sched.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "command.hpp"
#include "modbus/modbus_daq.hpp"
#include "modbus_sim_server.hpp"
#include "sim_panel.hpp"

namespace rig {
namespace {

using drivers::IoStatus;

class ModbusProtocolTest : public ::testing::Test {
 protected:
  void SetUp() override {
    server_ =
        std::make_unique<sim::ModbusSimServer>(physics_, sim::SimServerOptions{"127.0.0.1", 0});
    thread_ = std::thread([this] { server_->run(stop_); });
    // The simulated DAQ answers at real-time priority, as rig-sim does: on a busy machine a
    // normally scheduled server thread can stay off the CPU past any time-out.
    sched_param param{};
    param.sched_priority = 70;
    pthread_setschedparam(thread_.native_handle(), SCHED_FIFO,
                          &param);  // refused without privileges: fine
    drivers::ModbusDaqSettings s;
    s.port = server_->port();
    s.response_timeout_us = 5000;  // generous: these tests check behaviour, not speed
    s.watchdog_ms = 0;
    daq_ = std::make_unique<drivers::ModbusDaq>(s);
    panel_ = std::make_unique<testing::SimPanel>(server_->port());
  }
  void TearDown() override {
    panel_.reset();
    daq_.reset();
    stop_.store(true);
    thread_.join();
  }

  sim::RigPhysics physics_{sim::PhysicsParams{}};
  std::unique_ptr<sim::ModbusSimServer> server_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::unique_ptr<drivers::ModbusDaq> daq_;
  std::unique_ptr<testing::SimPanel> panel_;
};

TEST_F(ModbusProtocolTest, TheDriverReadsFreshCalibratedVoltagesEveryCycle) {
  drivers::AnalogFrame a, b;
  ASSERT_EQ(daq_->read(a), IoStatus::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_EQ(daq_->read(b), IoStatus::kOk);
  EXPECT_GT(b.sequence, a.sequence);
  // Carriage at 12 mm: 0.05 V + 0.2 V/mm; unloaded cell at its 0.08 V offset.
  EXPECT_NEAR(a.position_volts, 0.05 + 0.2 * 12.0, 0.01);
  EXPECT_NEAR(a.force_volts, 0.08, 0.02);
}

// A read that a busy machine made late (a time-out, or too soon for a new conversion) is
// tried again in the next cycle, as rigd's loop does; this test is about what the commands do.
IoStatus read_within_cycles(drivers::ModbusDaq& daq, drivers::AnalogFrame& frame, int cycles) {
  IoStatus status = IoStatus::kTimeout;
  for (int i = 0; i < cycles && status != IoStatus::kOk; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // one cycle = 1 ms
    status = daq.read(frame);
  }
  return status;
}

TEST_F(ModbusProtocolTest, DriveCommandsMoveTheSimulatedCarriage) {
  drivers::AnalogFrame frame;
  drivers::DigitalInputs inputs;
  ASSERT_EQ(read_within_cycles(*daq_, frame, 100), IoStatus::kOk);
  const double start_V = frame.position_volts;
  for (int i = 0; i < 200; ++i) {  // 200 answered cycles at +5 V (0.2 s or more), then stop
    ASSERT_EQ(read_within_cycles(*daq_, frame, 100), IoStatus::kOk) << "cycle " << i;
    ASSERT_EQ(daq_->read(inputs), IoStatus::kOk);
    daq_->write(drivers::DigitalOutputs{true, false});
    ASSERT_EQ(daq_->write(drivers::DriveCommand{true, 5.0, 0.0}), IoStatus::kOk);
  }
  daq_->write(drivers::DigitalOutputs{});
  ASSERT_EQ(read_within_cycles(*daq_, frame, 100), IoStatus::kOk);
  ASSERT_EQ(daq_->write(drivers::DriveCommand{}), IoStatus::kOk);
  ASSERT_EQ(read_within_cycles(*daq_, frame, 100), IoStatus::kOk);
  EXPECT_GT(frame.position_volts - start_V, 0.05);  // moved more than 0.25 mm into the eye
  EXPECT_FALSE(panel_->motor_powered());
}

TEST_F(ModbusProtocolTest, GarbageRepliesAreRejectedAsBadData) {
  panel_->set(proto::daq::sim_panel::kGarbageReplies, 1);
  drivers::AnalogFrame frame;
  EXPECT_EQ(daq_->read(frame), IoStatus::kBadData);
  panel_->set(proto::daq::sim_panel::kGarbageReplies, 0);
  EXPECT_EQ(daq_->read(frame), IoStatus::kOk);
}

TEST_F(ModbusProtocolTest, ALateReplyIsATimeoutThatDoesNotHangAndTheLinkRecovers) {
  panel_->set(proto::daq::sim_panel::kLateReplyUs, 20000);  // 20 ms > the 5 ms time-out
  drivers::AnalogFrame frame;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(daq_->read(frame), IoStatus::kTimeout);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(1000));
  panel_->set(proto::daq::sim_panel::kLateReplyUs, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  IoStatus status = IoStatus::kTimeout;
  for (int i = 0; i < 3 && status != IoStatus::kOk; ++i) status = daq_->read(frame);
  EXPECT_EQ(status, IoStatus::kOk);
  EXPECT_GE(daq_->counters().timeouts, 1U);
}

TEST_F(ModbusProtocolTest, WhileALateAnswerIsOnItsWayNoFurtherRequestQueuesBehindIt) {
  panel_->set(proto::daq::sim_panel::kLateReplyUs, 20000);  // 20 ms > the 5 ms time-out
  drivers::AnalogFrame frame;
  EXPECT_EQ(daq_->read(frame), IoStatus::kTimeout);
  const std::uint64_t sent = daq_->counters().transactions;
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(daq_->read(frame), IoStatus::kTimeout) << "the answer is still on its way";
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(2))
      << "waited for nothing";
  EXPECT_EQ(daq_->counters().transactions, sent) << "a request was queued behind the late one";
  panel_->set(proto::daq::sim_panel::kLateReplyUs, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(30));
  IoStatus status = IoStatus::kTimeout;
  for (int i = 0; i < 3 && status != IoStatus::kOk; ++i) status = daq_->read(frame);
  EXPECT_EQ(status, IoStatus::kOk);
}

TEST_F(ModbusProtocolTest, ADroppedLinkIsReportedAndReconnectedAfterItComesBack) {
  panel_->set(proto::daq::sim_panel::kLinkDrop, 20);  // 200 ms
  drivers::AnalogFrame frame;
  const IoStatus dropped = daq_->read(frame);
  EXPECT_TRUE(dropped == IoStatus::kLinkDown || dropped == IoStatus::kTimeout)
      << drivers::to_string(dropped);
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  IoStatus status = IoStatus::kLinkDown;
  for (int i = 0; i < 1000 && status != IoStatus::kOk;
       ++i) {  // reconnect attempts are spaced by cycles
    status = daq_->read(frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  EXPECT_EQ(status, IoStatus::kOk);
  EXPECT_GE(daq_->counters().reconnects, 1U);
}

TEST_F(ModbusProtocolTest, TheEstopButtonOnThePanelReachesTheDigitalInputs) {
  panel_->set(proto::daq::sim_panel::kEstopButton, 1);
  drivers::AnalogFrame frame;
  drivers::DigitalInputs inputs;
  ASSERT_EQ(daq_->read(frame), IoStatus::kOk);
  ASSERT_EQ(daq_->read(inputs), IoStatus::kOk);
  EXPECT_TRUE(inputs.estop);
}

std::string run_command(const std::string& command) {
  return testing::run_command(command).output;
}

TEST_F(ModbusProtocolTest, MbpollAnIndependentClientReadsTheRegisterMap) {
  const std::string port = std::to_string(server_->port());
  const std::string version =
      run_command("mbpoll -m tcp -p " + port + " -a 1 -r 12 -c 1 -t 3 -1 127.0.0.1");
  EXPECT_NE(version.find("[12]: \t1"), std::string::npos) << version;  // protocol version register
  const std::string volts =
      run_command("mbpoll -m tcp -p " + port + " -a 1 -r 5 -c 1 -t 3:float -B -1 127.0.0.1");
  const auto at = volts.find("[5]:");
  ASSERT_NE(at, std::string::npos) << volts;
  EXPECT_NEAR(std::stod(volts.substr(at + 5)), 0.05 + 0.2 * 12.0,
              0.01);  // position volts, float32 ABCD
}

TEST_F(ModbusProtocolTest, MbpollCanPressTheSimulatedEstop) {
  run_command("mbpoll -m tcp -p " + std::to_string(server_->port()) +
              " -a 1 -r 101 -t 4 -1 127.0.0.1 1");
  drivers::AnalogFrame frame;
  drivers::DigitalInputs inputs;
  ASSERT_EQ(daq_->read(frame), IoStatus::kOk);
  ASSERT_EQ(daq_->read(inputs), IoStatus::kOk);
  EXPECT_TRUE(inputs.estop);
}

}  // namespace
}  // namespace rig
