// The USB DAQ driver (libusb) against rig-usb-gadget, our FunctionFS device on the kernel's
// dummy_hcd (run inside the QEMU VM by scenario_usb.sh): the protocol end to end, the motor
// driven through it, the device's watchdog, and a hot-unplug (UDC unbound) read as a link
// loss, then found again when plugged back.
#include <gtest/gtest.h>

#include <thread>

#include "kernel_env.hpp"
#include "usb/usb_daq.hpp"

namespace rig::kernel_tests {
namespace {

using drivers::AnalogFrame;
using drivers::IoStatus;

struct Gadget : ::testing::Test {
  std::string gadget_dir = env_or_empty("RIG_USB_GADGET_DIR");
  std::string udc = env_or_empty("RIG_UDC");
  drivers::UsbDaqSettings settings;
  void SetUp() override {
    ASSERT_FALSE(gadget_dir.empty()) << "RIG_USB_GADGET_DIR not set: run inside the kernel VM (scenario_usb.sh)";
    settings.timeout_ms = 200;  // QEMU's TCG: a round trip takes far longer than on hardware
    settings.watchdog_ms = 50;
    settings.reconnect_every_cycles = 5;
  }
  static void wait_ms(int ms) { std::this_thread::sleep_for(std::chrono::milliseconds(ms)); }
  void drive(drivers::UsbDaq& daq, double volts, int cycles) {
    daq.write(drivers::DigitalOutputs{true, false});
    for (int i = 0; i < cycles; ++i) {
      AnalogFrame f;
      daq.read(f);
      ASSERT_EQ(daq.write(drivers::DriveCommand{true, volts, 0.0}), IoStatus::kOk);
      wait_ms(2);
    }
  }
};

TEST_F(Gadget, GreetsTheDeviceAndReadsFreshConversions) {
  drivers::UsbDaq daq(settings);
  EXPECT_EQ(daq.hello().channels, 3);
  AnalogFrame a, b;
  ASSERT_EQ(daq.read(a), IoStatus::kOk);
  ASSERT_EQ(daq.read(b), IoStatus::kOk);
  EXPECT_GT(b.sequence, a.sequence);
  drivers::DigitalInputs in;
  EXPECT_EQ(daq.read(in), IoStatus::kOk);
  EXPECT_FALSE(in.estop);
}

TEST_F(Gadget, DrivesTheMotorThroughTheDevice) {
  drivers::UsbDaq daq(settings);
  AnalogFrame before, after;
  ASSERT_EQ(daq.read(before), IoStatus::kOk);
  drive(daq, -6.0, 100);
  ASSERT_EQ(daq.read(after), IoStatus::kOk);
  EXPECT_GT(std::abs(after.position_volts - before.position_volts), 0.01) << "the carriage did not move";
  EXPECT_EQ(daq.write(drivers::DriveCommand{}), IoStatus::kOk);
}

TEST_F(Gadget, TheDeviceDropsItsOutputsWhenTheHostFallsSilent) {
  drivers::UsbDaq daq(settings);
  drive(daq, 0.5, 5);
  wait_ms(300);  // > watchdog_ms of silence
  AnalogFrame f;
  ASSERT_EQ(daq.read(f), IoStatus::kOk);
  EXPECT_TRUE(daq.device_watchdog_tripped());
}

TEST_F(Gadget, AnUnpluggedDeviceIsALinkLossAndIsFoundAgainWhenPluggedBack) {
  drivers::UsbDaq daq(settings);
  AnalogFrame f;
  ASSERT_EQ(daq.read(f), IoStatus::kOk);
  ASSERT_TRUE(write_attribute(gadget_dir + "/UDC", "\n")) << "unbinding the UDC (pulling the cable)";
  IoStatus status = IoStatus::kOk;
  for (int i = 0; i < 50 && status == IoStatus::kOk; ++i) {
    status = daq.read(f);
    wait_ms(20);
  }
  EXPECT_EQ(status, IoStatus::kLinkDown);
  EXPECT_FALSE(daq.connected());
  EXPECT_GE(daq.counters().link_errors, 1U);
  ASSERT_TRUE(write_attribute(gadget_dir + "/UDC", udc)) << "binding " << udc << " again";
  for (int i = 0; i < 500 && status != IoStatus::kOk; ++i) {
    status = daq.read(f);
    wait_ms(20);
  }
  EXPECT_EQ(status, IoStatus::kOk) << "the device was not found again";
  EXPECT_GE(daq.counters().reconnects, 1U);
}

}  // namespace
}  // namespace rig::kernel_tests
