#pragma once
// Decoding of the DAQ's Modbus input block (docs/register-map.md): protocol version, three
// analog channels as IEEE-754 floats (high word first), the conversion counter and the
// digital input bits. Pure and allocation-free: used by ModbusDaq every cycle and by the
// fuzz target `fuzz_modbus_response`.
#include <cstdint>
#include <optional>
#include <span>

#include "rig/drivers/analog_input.hpp"
#include "rig/drivers/digital_io.hpp"

namespace rig::drivers {

struct DecodedInputBlock {
  AnalogFrame frame;
  DigitalInputs digital;
};

// nullopt: too short, wrong protocol version, or a channel not finite / beyond ±max_abs_volts.
std::optional<DecodedInputBlock> decode_input_block(std::span<const std::uint16_t> block,
                                                    double max_abs_volts) noexcept;

}  // namespace rig::drivers
