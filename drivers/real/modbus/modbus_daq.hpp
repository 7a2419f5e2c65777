#pragma once
// The rig's DAQ over Modbus (TCP, or RTU on a serial line). Per loop cycle it makes two
// transactions: AnalogInput::read() reads the whole input block (analog channels and the
// digital input bits), ActuatorDrive::write() writes the whole output block (motor, pump
// and the digital outputs that DigitalIo::write() staged in the same cycle).
#include <cstdint>
#include <string>

#include "modbus_context.hpp"
#include "rig/drivers/actuator_drive.hpp"
#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"
#include "rig/drivers/link_counters.hpp"

namespace rig::drivers {

struct ModbusDaqSettings {
  std::string transport = "tcp";  // "tcp" or "rtu"
  std::string host = "127.0.0.1";
  int port = 1502;
  std::string serial_device;  // RTU: /dev/ttyUSB0
  int baud = 115200;
  char parity = 'N';
  int data_bits = 8;
  int stop_bits = 1;
  int unit_id = 1;
  int response_timeout_us = 700;  // < one loop period, so a lost reply never hangs the loop
  int watchdog_ms = 5;            // DAQ drops its outputs after this much silence
  int reconnect_every_cycles = 200;
  double max_abs_volts = 12.0;  // readings outside are garbage
};

class ModbusDaq final : public AnalogInput, public ActuatorDrive, public DigitalIo {
 public:
  // Connects and checks the protocol version; throws std::runtime_error (setup only).
  explicit ModbusDaq(const ModbusDaqSettings& settings);

  IoStatus read(AnalogFrame& frame) noexcept override;
  IoStatus read(DigitalInputs& inputs) noexcept override;           // from this cycle's input block
  IoStatus write(const DigitalOutputs& outputs) noexcept override;  // staged for write(Drive)
  IoStatus write(const DriveCommand& command) noexcept override;
  LinkCounters counters() const noexcept { return counters_; }
  bool connected() const noexcept { return connected_; }

 private:
  IoStatus fail(int error_number) noexcept;
  IoStatus ensure_connected() noexcept;
  IoStatus validate(const std::uint16_t* block, AnalogFrame& frame) noexcept;

  ModbusDaqSettings settings_;
  ModbusContextPtr ctx_;
  bool connected_ = false;
  bool flush_before_next_ = false;
  bool awaiting_late_reply_ = false;  // the last request timed out; its answer may still come
  int cycles_awaiting_ = 0;
  static constexpr int kMaxCyclesAwaiting = 2;  // cycles to wait for it before asking anew
  int cycles_since_attempt_ = 0;
  IoStatus input_status_ = IoStatus::kNotReady;
  DigitalInputs digital_{};  // from this cycle's input block
  DigitalOutputs staged_outputs_{};
  std::uint32_t last_sequence_ = 0;
  LinkCounters counters_{};
};

}  // namespace rig::drivers
