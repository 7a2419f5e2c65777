#pragma once
// The rig's DAQ on USB (libusb-1.0), speaking docs/usb-daq-protocol.md: per loop cycle one
// READ_INPUTS round trip in read() and one WRITE_OUTPUTS round trip in write(). An unplugged
// device reads as kLinkDown, exactly like a dropped Modbus link; the driver looks for it
// again every reconnect_every_cycles and carries on when it is back. The device is found
// through sysfs and opened with libusb_wrap_sys_device, so hot-plug works without udevd.
#include <cstdint>
#include <memory>
#include <string>

#include "rig/drivers/actuator_drive.hpp"
#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/drivers/link_counters.hpp"
#include "usb_daq_protocol.hpp"

struct libusb_context;
struct libusb_device_handle;

namespace rig::drivers {

struct UsbDaqSettings {
  int vendor_id = 0x1d6b;
  int product_id = 0x0104;
  std::string serial;  // empty = the first matching device
  std::string sysfs_root = "/sys/bus/usb/devices";
  std::string devfs_root = "/dev/bus/usb";
  unsigned timeout_ms = 2;  // per transfer; libusb's resolution is 1 ms
  int watchdog_ms = 5;      // the DAQ drops its outputs after this much silence
  int reconnect_every_cycles = 200;
  double max_abs_volts = 12.0;  // readings outside are garbage
};

class UsbDaq final : public AnalogInput, public ActuatorDrive, public DigitalIo {
 public:
  // Finds, opens and greets the device; throws naming VID:PID and the reason (setup only).
  explicit UsbDaq(const UsbDaqSettings& settings);
  ~UsbDaq() override;
  UsbDaq(const UsbDaq&) = delete;
  UsbDaq& operator=(const UsbDaq&) = delete;

  IoStatus read(AnalogFrame& frame) noexcept override;
  IoStatus read(DigitalInputs& inputs) noexcept override;
  IoStatus write(const DigitalOutputs& outputs) noexcept override;  // staged for write(Drive)
  IoStatus write(const DriveCommand& command) noexcept override;
  bool connected() const noexcept { return handle_ != nullptr; }
  bool device_watchdog_tripped() const noexcept { return watchdog_tripped_; }
  LinkCounters counters() const noexcept { return counters_; }
  usbdaq::HelloReply hello() const noexcept { return hello_; }

 private:
  struct ContextDeleter {
    void operator()(libusb_context* ctx) const noexcept;
  };
  bool open_device(std::string& why) noexcept;
  bool find_bulk_endpoints(libusb_device_handle* handle) noexcept;
  void close_device() noexcept;
  IoStatus ensure_connected() noexcept;
  IoStatus transact(usbdaq::Opcode opcode, std::span<const std::uint8_t> payload,
                    usbdaq::Message& reply, std::span<const std::uint8_t>& reply_payload) noexcept;
  IoStatus fail(int libusb_error) noexcept;

  UsbDaqSettings settings_;
  std::unique_ptr<libusb_context, ContextDeleter> ctx_;
  libusb_device_handle* handle_ = nullptr;  // closed in close_device()
  int device_fd_ = -1;
  unsigned char ep_in_ = 0x81, ep_out_ = 0x02;
  static constexpr int kHelloAttempts = 3;  // greetings before the constructor gives up
  static constexpr int kStaleRepliesSkipped =
      8;  // queued replies of earlier requests read past per request
  std::uint16_t sequence_ = 0;
  int cycles_since_attempt_ = 0;
  usbdaq::HelloReply hello_{};
  usbdaq::InputsReply inputs_{};
  IoStatus input_status_ = IoStatus::kNotReady;
  std::uint32_t last_sequence_ = 0;
  bool have_sequence_ = false;
  bool watchdog_tripped_ = false;
  DigitalOutputs staged_outputs_{};
  LinkCounters counters_{};
};

}  // namespace rig::drivers
