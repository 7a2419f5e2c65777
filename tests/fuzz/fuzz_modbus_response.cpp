// libFuzzer target: the decoder of the DAQ's Modbus input block (the registers of each
// cycle's response). Any 12 registers either decode to finite volts within range or are
// refused.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include "modbus/input_block.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::uint16_t> registers(size / 2);
  if (!registers.empty()) std::memcpy(registers.data(), data, registers.size() * 2);
  const auto decoded = rig::drivers::decode_input_block(registers, 12.0);
  if (decoded &&
      !(std::isfinite(decoded->frame.force_volts) && std::abs(decoded->frame.force_volts) <= 12.0 &&
        std::isfinite(decoded->frame.iop_volts) && std::isfinite(decoded->frame.position_volts)))
    __builtin_trap();  // accepted something it must refuse
  return 0;
}
