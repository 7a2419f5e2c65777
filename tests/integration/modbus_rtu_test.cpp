// Modbus RTU: the DAQ driver and mbpoll against the simulated rig over a serial line
// (a socat pty pair: a real tty to both libmodbus and mbpoll, without baud-rate timing).
// The simulator keeps its TCP panel, so faults can be injected while the DAQ talks RTU.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <thread>

#include "command.hpp"
#include "modbus/modbus_daq.hpp"
#include "modbus_sim_server.hpp"
#include "sim_panel.hpp"
#include "test_paths.hpp"

namespace rig {
namespace {

using drivers::IoStatus;

// socat linking two ptys at <dir>/ttyDAQ (the simulator's end) and <dir>/ttyHOST (ours).
class PtyPair {
 public:
  explicit PtyPair(const testing::ScratchDir& dir)
      : daq_(dir.file("ttyDAQ")), host_(dir.file("ttyHOST")) {
    pid_ = fork();
    if (pid_ == 0) {
      execlp("socat", "socat", ("pty,raw,echo=0,link=" + daq_).c_str(),
             ("pty,raw,echo=0,link=" + host_).c_str(), static_cast<char*>(nullptr));
      _exit(127);
    }
    for (int i = 0; i < 100 && !(std::filesystem::exists(daq_) && std::filesystem::exists(host_));
         ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  ~PtyPair() {
    kill(pid_, SIGTERM);
    waitpid(pid_, nullptr, 0);
  }
  bool ready() const { return std::filesystem::exists(daq_) && std::filesystem::exists(host_); }
  const std::string& daq_end() const { return daq_; }
  const std::string& host_end() const { return host_; }

 private:
  std::string daq_, host_;
  pid_t pid_ = -1;
};

class ModbusRtuTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(pty_.ready()) << "socat did not create the pty pair";
    sim::SimServerOptions options{"127.0.0.1", 0};
    options.rtu_device = pty_.daq_end();
    server_ = std::make_unique<sim::ModbusSimServer>(physics_, options);
    thread_ = std::thread([this] { server_->run(stop_); });
    panel_ = std::make_unique<testing::SimPanel>(server_->port());
  }
  void TearDown() override {
    panel_.reset();
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }
  // [us] response timeout: 250 ms where a test checks behaviour, not timing (20 ms timed out
  // under ./rig stress: socat and the simulator thread were not scheduled in time).
  drivers::ModbusDaqSettings rtu_settings(int response_timeout_us = 250000) const {
    drivers::ModbusDaqSettings s;
    s.transport = "rtu";
    s.serial_device = pty_.host_end();
    s.baud = 115200;
    s.response_timeout_us = response_timeout_us;  // a pty is not timed like a line
    s.watchdog_ms = 0;
    return s;
  }

  testing::ScratchDir dir_{"rtu"};
  PtyPair pty_{dir_};
  sim::RigPhysics physics_{sim::PhysicsParams{}};
  std::unique_ptr<sim::ModbusSimServer> server_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::unique_ptr<testing::SimPanel> panel_;
};

TEST_F(ModbusRtuTest, TheDaqDriverReadsCalibratedVoltagesAndDrivesTheCarriageOverRtu) {
  drivers::ModbusDaq daq(rtu_settings());
  drivers::AnalogFrame frame;
  ASSERT_EQ(daq.read(frame), IoStatus::kOk);
  EXPECT_NEAR(frame.position_volts, 0.05 + 0.2 * 12.0, 0.01);  // carriage parked at 12 mm
  const double start_V = frame.position_volts;
  for (int i = 0; i < 100; ++i) {
    std::this_thread::sleep_for(
        std::chrono::milliseconds(2));  // sooner than a conversion is kStale
    ASSERT_EQ(daq.read(frame), IoStatus::kOk);
    daq.write(drivers::DigitalOutputs{true, false});
    ASSERT_EQ(daq.write(drivers::DriveCommand{true, 5.0, 0.0}), IoStatus::kOk);
  }
  daq.write(drivers::DigitalOutputs{});
  ASSERT_EQ(daq.write(drivers::DriveCommand{}), IoStatus::kOk);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  ASSERT_EQ(daq.read(frame), IoStatus::kOk);
  EXPECT_GT(frame.position_volts - start_V, 0.05);
  EXPECT_FALSE(panel_->motor_powered());
  EXPECT_EQ(daq.counters().timeouts, 0U);
}

TEST_F(ModbusRtuTest, ASilentLineIsATimeoutThatDoesNotHangAndTheLinkRecovers) {
  drivers::ModbusDaq daq(rtu_settings(20000));  // [us] this test is about the timeout
  drivers::AnalogFrame frame;
  // The line answers (a busy machine may miss the 20 ms once: not what this test is about).
  IoStatus first = IoStatus::kTimeout;
  for (int i = 0; i < 20 && first != IoStatus::kOk; ++i) first = daq.read(frame);
  ASSERT_EQ(first, IoStatus::kOk);
  const std::uint64_t timeouts_before = daq.counters().timeouts;
  // The DAQ stops answering on the line for 300 ms (units of 10 ms; the drop also closes the
  // TCP panel's connection, so it clears itself).
  panel_->set(proto::daq::sim_panel::kLinkDrop, 30);
  const auto t0 = std::chrono::steady_clock::now();
  EXPECT_EQ(daq.read(frame), IoStatus::kTimeout);
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(200));
  std::this_thread::sleep_for(std::chrono::milliseconds(400));
  IoStatus status = IoStatus::kTimeout;
  for (int i = 0; i < 20 && status != IoStatus::kOk; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    status = daq.read(frame);
  }
  EXPECT_EQ(status, IoStatus::kOk);
  EXPECT_GE(daq.counters().timeouts, timeouts_before + 1);
}

TEST_F(ModbusRtuTest, GarbageOverRtuIsRejectedAsBadData) {
  drivers::ModbusDaq daq(rtu_settings());
  panel_->set(proto::daq::sim_panel::kGarbageReplies, 1);
  drivers::AnalogFrame frame;
  EXPECT_EQ(daq.read(frame), IoStatus::kBadData);
  panel_->set(proto::daq::sim_panel::kGarbageReplies, 0);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_EQ(daq.read(frame), IoStatus::kOk);
}

TEST_F(ModbusRtuTest, MbpollAnIndependentRtuClientReadsTheRegisterMap) {
  const std::string line = " -m rtu -a 1 -b 115200 -P none -1 " + pty_.host_end();
  const auto version = testing::run_command("mbpoll -r 12 -c 1 -t 3" + line);
  EXPECT_NE(version.output.find("[12]: \t1"), std::string::npos)
      << version.output;  // protocol version register
  const auto volts = testing::run_command("mbpoll -r 5 -c 1 -t 3:float -B" + line);
  const auto at = volts.output.find("[5]:");
  ASSERT_NE(at, std::string::npos) << volts.output;
  EXPECT_NEAR(std::stod(volts.output.substr(at + 5)), 0.05 + 0.2 * 12.0, 0.01);
}

TEST(ModbusRtu, AMissingSerialDeviceIsAClearErrorAtSetup) {
  drivers::ModbusDaqSettings s;
  s.transport = "rtu";
  s.serial_device = "/dev/ttyNOPE9";
  try {
    drivers::ModbusDaq daq(s);
    FAIL() << "opened a missing serial device";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/dev/ttyNOPE9"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig
