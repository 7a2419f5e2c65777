#include "input_block.hpp"

#include <cmath>

#include "rig/proto/daq_register_map.hpp"

namespace rig::drivers {

namespace reg = proto::daq;

std::optional<DecodedInputBlock> decode_input_block(std::span<const std::uint16_t> block,
                                                    double max_abs_volts) noexcept {
  if (block.size() < static_cast<std::size_t>(reg::input::kCount)) return std::nullopt;
  if (block[reg::input::kVersion] != reg::kProtocolVersion) return std::nullopt;
  const float volts[3] = {reg::decode_f32(block.data() + reg::input::kForceVolts),
                          reg::decode_f32(block.data() + reg::input::kPositionVolts),
                          reg::decode_f32(block.data() + reg::input::kIopVolts)};
  for (const float v : volts) {
    if (!std::isfinite(v) || std::abs(v) > max_abs_volts) return std::nullopt;
  }
  DecodedInputBlock out;
  out.frame.force_volts = volts[0];
  out.frame.position_volts = volts[1];
  out.frame.iop_volts = volts[2];
  out.frame.sequence = reg::decode_u32(block.data() + reg::input::kSequence);
  const std::uint16_t bits = block[reg::input::kDigitalInputs];
  out.digital.home_limit = (bits & reg::input_bit::kHomeLimit) != 0;
  out.digital.end_limit = (bits & reg::input_bit::kEndLimit) != 0;
  out.digital.estop = (bits & reg::input_bit::kEstop) != 0;
  out.digital.drive_fault = (bits & reg::input_bit::kDriveFault) != 0;
  out.digital.daq_watchdog_tripped = (bits & reg::input_bit::kWatchdogTripped) != 0;
  return out;
}

}  // namespace rig::drivers
