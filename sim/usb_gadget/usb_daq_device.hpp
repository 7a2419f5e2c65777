#pragma once
// The device side of docs/usb-daq-protocol.md: what the DAQ's firmware does with each
// request, over the simulated rig's physics on a wall clock. Transport-free (FunctionFS
// endpoints in the gadget, a byte span in unit tests and fuzzing).
#include <cstdint>
#include <mutex>
#include <span>

#include "rig/sim/rig_physics.hpp"
#include "usb/usb_daq_protocol.hpp"

namespace rig::sim {

class UsbDaqDevice {
 public:
  explicit UsbDaqDevice(RigPhysics& physics) : physics_(&physics) {}
  // One request in, one response out; returns the response length [B] (0 = ignore the
  // request: not even a header to answer). now_s: the device's clock [s].
  std::size_t handle(std::span<const std::uint8_t> request, drivers::usbdaq::Message& response,
                     double now_s);
  std::uint64_t requests() const { return requests_; }

 private:
  RigPhysics* physics_;
  std::mutex mutex_;  // the gadget's endpoint thread and a test panel may both reach the physics
  std::uint32_t conversions_ = 0;
  std::uint64_t requests_ = 0;
};

}  // namespace rig::sim
