// The USB DAQ driver (libusb) against rig-usb-gadget, our FunctionFS device on the kernel's
// dummy_hcd (run inside the QEMU VM by scenario_usb.sh): the protocol end to end, the motor
// driven through it, the device's watchdog, and a hot-unplug (UDC unbound) read as a link
// loss, then found again when plugged back.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <libusb-1.0/libusb.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ios>
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
    ASSERT_FALSE(gadget_dir.empty())
        << "RIG_USB_GADGET_DIR not set: run inside the kernel VM (scenario_usb.sh)";
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
  EXPECT_GT(std::abs(after.position_volts - before.position_volts), 0.01)
      << "the carriage did not move";
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

// Sends one HELLO with sequence 1 straight through libusb and leaves without reading its
// reply: what a session leaves queued when its greeting times out (rigd restarted, or a host
// stalled past the time-out). Returns false if the device could not be reached.
bool leave_a_hello_reply_queued(const drivers::UsbDaqSettings& settings) {
  libusb_set_option(nullptr,
                    LIBUSB_OPTION_NO_DEVICE_DISCOVERY);  // as the driver: no udevd in the VM
  for (const auto& entry : std::filesystem::directory_iterator(settings.sysfs_root)) {
    std::ifstream vendor(entry.path() / "idVendor"), product(entry.path() / "idProduct"),
        bus(entry.path() / "busnum"), dev(entry.path() / "devnum");
    int vid = 0, pid = 0, busnum = 0, devnum = 0;
    if (!(vendor >> std::hex >> vid && product >> std::hex >> pid && bus >> busnum &&
          dev >> devnum))
      continue;
    if (vid != settings.vendor_id || pid != settings.product_id) continue;
    char node[64];
    std::snprintf(node, sizeof node, "%s/%03d/%03d", settings.devfs_root.c_str(), busnum, devnum);
    const int fd = ::open(node, O_RDWR | O_CLOEXEC);
    libusb_context* ctx = nullptr;
    libusb_device_handle* handle = nullptr;
    bool sent = false;
    if (fd >= 0 && libusb_init(&ctx) == 0 && libusb_wrap_sys_device(ctx, fd, &handle) == 0 &&
        libusb_claim_interface(handle, 0) == 0) {
      drivers::usbdaq::Message request{};
      const std::size_t length =
          drivers::usbdaq::encode_request(request, drivers::usbdaq::Opcode::kHello, 1);
      unsigned char out_endpoint = 0;  // FunctionFS may renumber it: read it back
      libusb_config_descriptor* config = nullptr;
      if (libusb_get_active_config_descriptor(libusb_get_device(handle), &config) == 0) {
        const libusb_interface_descriptor& interface = config->interface[0].altsetting[0];
        for (int i = 0; i < interface.bNumEndpoints; ++i) {
          if ((interface.endpoint[i].bEndpointAddress & LIBUSB_ENDPOINT_IN) == 0)
            out_endpoint = interface.endpoint[i].bEndpointAddress;
        }
        libusb_free_config_descriptor(config);
      }
      int done = 0;
      sent = out_endpoint != 0 && libusb_bulk_transfer(handle, out_endpoint, request.data(),
                                                       static_cast<int>(length), &done, 1000) == 0;
      libusb_release_interface(handle, 0);
    }
    if (handle != nullptr) libusb_close(handle);
    if (ctx != nullptr) libusb_exit(ctx);
    if (fd >= 0) ::close(fd);
    return sent;
  }
  return false;
}

// Under TCG on a busy host a greeting took longer than its time-out, and the device's late
// reply to it (sequence 1) was taken by the next session as the answer to its own sequence 1;
// that session's own reply then came back to its first read as garbage, and every later test
// failed the same way (2026-11-29). The next session must skip a reply it did not ask for.
TEST_F(Gadget, AnEarlierSessionsLateReplyIsNotTakenForThisOnes) {
  ASSERT_TRUE(leave_a_hello_reply_queued(settings)) << "could not send the abandoned greeting";
  wait_ms(300);  // the reply reaches the device's IN queue
  drivers::UsbDaq daq(settings);
  EXPECT_EQ(daq.hello().channels, 3);
  for (int i = 0; i < 5; ++i) {
    AnalogFrame f;
    ASSERT_EQ(daq.read(f), IoStatus::kOk) << "read " << i;
    ASSERT_EQ(daq.write(drivers::DriveCommand{}), IoStatus::kOk) << "write " << i;
  }
}

TEST_F(Gadget, AnUnpluggedDeviceIsALinkLossAndIsFoundAgainWhenPluggedBack) {
  drivers::UsbDaq daq(settings);
  AnalogFrame f;
  ASSERT_EQ(daq.read(f), IoStatus::kOk);
  ASSERT_TRUE(write_attribute(gadget_dir + "/UDC", "\n"))
      << "unbinding the UDC (pulling the cable)";
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
