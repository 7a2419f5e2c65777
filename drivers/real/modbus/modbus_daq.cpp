#include "modbus_daq.hpp"

#include <modbus/modbus.h>

#include <cerrno>
#include <cmath>
#include <stdexcept>

#include "input_block.hpp"
#include "rig/proto/daq_register_map.hpp"

namespace rig::drivers {
namespace reg = rig::proto::daq;

ModbusDaq::ModbusDaq(const ModbusDaqSettings& settings) : settings_(settings) {
  ctx_ = settings.transport == "rtu"
             ? make_modbus_rtu(settings.serial_device, settings.baud, settings.parity,
                               settings.data_bits, settings.stop_bits)
             : make_modbus_tcp(settings.host, settings.port);
  modbus_set_slave(ctx_.get(), settings.unit_id);
  // Never let libmodbus sleep or reconnect on its own inside the loop.
  modbus_set_error_recovery(ctx_.get(), MODBUS_ERROR_RECOVERY_NONE);
  const std::string where = settings.transport == "rtu"
                                ? settings.serial_device
                                : settings.host + ":" + std::to_string(settings.port);
  // Setup may wait longer than a cycle; the loop timeout is set after the first exchange.
  modbus_set_response_timeout(ctx_.get(), 1, 0);
  if (modbus_connect(ctx_.get()) != 0) {
    throw std::runtime_error("DAQ at " + where + ": cannot connect: " + modbus_strerror(errno));
  }
  connected_ = true;
  std::uint16_t block[reg::input::kCount] = {};
  if (modbus_read_input_registers(ctx_.get(), 0, reg::input::kCount, block) != reg::input::kCount) {
    throw std::runtime_error("DAQ at " + where +
                             ": no answer to the first read: " + modbus_strerror(errno));
  }
  if (block[reg::input::kVersion] != reg::kProtocolVersion) {
    throw std::runtime_error("DAQ at " + where + ": protocol version " +
                             std::to_string(block[reg::input::kVersion]) + ", expected " +
                             std::to_string(reg::kProtocolVersion));
  }
  const auto timeout_us = static_cast<std::uint32_t>(settings.response_timeout_us);
  modbus_set_response_timeout(ctx_.get(), timeout_us / 1'000'000U, timeout_us % 1'000'000U);
  modbus_set_byte_timeout(ctx_.get(), timeout_us / 1'000'000U, timeout_us % 1'000'000U);
}

IoStatus ModbusDaq::fail(int error_number) noexcept {
  const IoStatus status = io_status_from_errno(error_number);
  switch (status) {
    case IoStatus::kTimeout:
      ++counters_.timeouts;
      break;
    case IoStatus::kLinkDown:
      ++counters_.link_errors;
      break;
    default:
      ++counters_.bad_data;
      break;
  }
  if (status == IoStatus::kLinkDown) {
    modbus_close(ctx_.get());
    connected_ = false;
    cycles_since_attempt_ = settings_.reconnect_every_cycles;  // the next cycle retries at once
  } else {
    // A late answer (time-out) or one out of step (an earlier late answer, wrong transaction
    // id): drop what is there now, and again before the next request, when the answer still
    // in flight has had a cycle to arrive. The stream is back in step within one cycle.
    modbus_flush(ctx_.get());
    flush_before_next_ = true;
    awaiting_late_reply_ = status == IoStatus::kTimeout;
    cycles_awaiting_ = 0;
  }
  return status;
}

IoStatus ModbusDaq::ensure_connected() noexcept {
  if (connected_) return IoStatus::kOk;
  if (++cycles_since_attempt_ < settings_.reconnect_every_cycles) return IoStatus::kLinkDown;
  cycles_since_attempt_ = 0;
  // A refused connect returns at once; an unanswered one within the response timeout.
  if (modbus_connect(ctx_.get()) != 0) {
    modbus_close(ctx_.get());
    return IoStatus::kLinkDown;
  }
  connected_ = true;
  ++counters_.reconnects;
  return IoStatus::kOk;
}

IoStatus ModbusDaq::validate(const std::uint16_t* block, AnalogFrame& frame) noexcept {
  const auto decoded = decode_input_block(std::span<const std::uint16_t>(block, reg::input::kCount),
                                          settings_.max_abs_volts);
  if (!decoded) return IoStatus::kBadData;
  frame = decoded->frame;
  digital_ = decoded->digital;
  const bool fresh = frame.sequence != last_sequence_;
  last_sequence_ = frame.sequence;
  return fresh ? IoStatus::kOk : IoStatus::kStale;
}

IoStatus ModbusDaq::read(AnalogFrame& frame) noexcept {
  input_status_ = ensure_connected();
  if (input_status_ != IoStatus::kOk) return input_status_;
  if (flush_before_next_) {
    const int flushed = modbus_flush(ctx_.get());
    // The answer to a timed-out request is still on its way: a request sent now would queue
    // behind it in the DAQ, and a slow DAQ would never catch up. One outstanding request at a
    // time, as a Modbus master on a line; after kMaxCyclesAwaiting the answer counts as lost.
    if (awaiting_late_reply_ && flushed <= 0 && ++cycles_awaiting_ < kMaxCyclesAwaiting) {
      ++counters_.timeouts;
      input_status_ = IoStatus::kTimeout;
      return input_status_;
    }
    flush_before_next_ = false;
    awaiting_late_reply_ = false;
  }
  ++counters_.transactions;
  std::uint16_t block[reg::input::kCount] = {};
  if (modbus_read_input_registers(ctx_.get(), 0, reg::input::kCount, block) != reg::input::kCount) {
    input_status_ = fail(errno);
    return input_status_;
  }
  input_status_ = validate(block, frame);
  if (input_status_ == IoStatus::kBadData) ++counters_.bad_data;
  return input_status_;
}

IoStatus ModbusDaq::read(DigitalInputs& inputs) noexcept {
  if (input_status_ != IoStatus::kOk && input_status_ != IoStatus::kStale) return input_status_;
  inputs = digital_;
  return IoStatus::kOk;
}

IoStatus ModbusDaq::write(const DigitalOutputs& outputs) noexcept {
  staged_outputs_ = outputs;
  return IoStatus::kOk;
}

IoStatus ModbusDaq::write(const DriveCommand& command) noexcept {
  if (!connected_) return IoStatus::kLinkDown;
  // After a failed read the late reply may still be in flight: do not put another request
  // behind it. The DAQ keeps its last outputs, and its watchdog stops the motor if the link
  // stays silent.
  if (input_status_ != IoStatus::kOk && input_status_ != IoStatus::kStale) return input_status_;
  std::uint16_t block[reg::holding::kCount] = {};
  std::uint16_t bits = 0;
  if (command.motor_enable && staged_outputs_.motor_enable) bits |= reg::output_bit::kMotorEnable;
  if (staged_outputs_.camera_trigger) bits |= reg::output_bit::kCameraTrigger;
  block[reg::holding::kDigitalOutputs] = bits;
  reg::encode_f32(static_cast<float>(command.motor_enable ? command.motor_volts : 0.0),
                  block + reg::holding::kMotorVolts);
  reg::encode_f32(static_cast<float>(command.pump_command), block + reg::holding::kPumpCommand);
  block[reg::holding::kWatchdogMs] = static_cast<std::uint16_t>(settings_.watchdog_ms);
  ++counters_.transactions;
  if (modbus_write_registers(ctx_.get(), 0, reg::holding::kCount, block) != reg::holding::kCount) {
    return fail(errno);
  }
  return IoStatus::kOk;
}

}  // namespace rig::drivers
