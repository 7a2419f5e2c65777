// rig-usb-gadget: the simulated rig as a USB DAQ, through FunctionFS (docs/usb-daq-protocol.md).
//   rig-usb-gadget FFS_DIR        (FunctionFS mounted at FFS_DIR, then bind the gadget's UDC)
#include <csignal>
#include <cstdio>
#include <ctime>
#include <exception>

#include "functionfs_gadget.hpp"
#include "usb_daq_device.hpp"

namespace {
std::atomic<bool> g_stop{false};
void on_signal(int) {
  g_stop.store(true);
}
double monotonic_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + ts.tv_nsec * 1e-9;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: rig-usb-gadget FFS_DIR\n");
    return 2;
  }
  std::signal(SIGTERM, on_signal);
  std::signal(SIGINT, on_signal);
  try {
    rig::sim::RigPhysics physics(rig::sim::PhysicsParams{});
    rig::sim::UsbDaqDevice device(physics);
    const double start = monotonic_s();
    rig::sim::FunctionFsGadget gadget(argv[1], [&](std::span<const std::uint8_t> request,
                                                   rig::drivers::usbdaq::Message& response) {
      return device.handle(request, response, monotonic_s() - start);
    });
    std::printf("rig-usb-gadget: descriptors written to %s/ep0, serving\n", argv[1]);
    std::fflush(stdout);
    gadget.serve(g_stop);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rig-usb-gadget: %s\n", e.what());
    return 1;
  }
  return 0;
}
