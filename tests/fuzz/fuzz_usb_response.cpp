// libFuzzer target: the USB DAQ protocol decoders (docs/usb-daq-protocol.md) on any bytes,
// and the simulated device answering them (a firmware must survive any request too).
#include <cstddef>
#include <cstdint>
#include <span>

#include "usb/usb_daq_protocol.hpp"
#include "usb_daq_device.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  namespace usbdaq = rig::drivers::usbdaq;
  const std::span<const std::uint8_t> bytes(data, size);
  if (const auto header = usbdaq::decode_header(bytes)) {
    if (usbdaq::kHeaderSize + header->length != size) __builtin_trap();
    const auto payload = bytes.subspan(usbdaq::kHeaderSize);
    (void)usbdaq::decode_hello(payload);
    (void)usbdaq::decode_inputs(payload);
    (void)usbdaq::decode_outputs(payload);
  }
  static rig::sim::RigPhysics physics{rig::sim::PhysicsParams{}};
  static rig::sim::UsbDaqDevice device{physics};
  static double now_s = 0.0;
  usbdaq::Message reply{};
  const std::size_t n = device.handle(bytes, reply, now_s += 1e-3);
  if (n > reply.size()) __builtin_trap();
  if (n > 0 && !usbdaq::decode_header(std::span<const std::uint8_t>(reply.data(), n)))
    __builtin_trap();  // answers must be well-formed
  return 0;
}
