#pragma once
// Modbus register map of the rig's DAQ: the one definition shared by the driver (client)
// and the simulated rig (server). Documented for technicians in docs/register-map.md.
// 32-bit values are big-endian words ("ABCD": high word at the lower address).
//
// libmodbus 3.1.6's modbus_set_float_*() write the wrong word order (upstream #611, #807),
// so floats are encoded here, independent of the library version.
#include <bit>
#include <cstdint>

namespace rig::proto::daq {

inline constexpr int kUnitId = 1;
inline constexpr std::uint16_t kProtocolVersion = 1;

// Input registers (function 4): one read per loop cycle.
namespace input {
inline constexpr int kSequence = 0;       // u32 conversion counter
inline constexpr int kForceVolts = 2;     // f32 load-cell amplifier [V]
inline constexpr int kPositionVolts = 4;  // f32 potentiometer [V]
inline constexpr int kIopVolts = 6;       // f32 IOP transducer [V]
inline constexpr int kDigitalInputs = 8;  // u16 bit field, see bits below
inline constexpr int kDaqTimeUs = 9;      // u32 DAQ clock [us], wraps
inline constexpr int kVersion = 11;       // u16 protocol version
inline constexpr int kCount = 12;         // registers read per cycle
}  // namespace input

namespace input_bit {
inline constexpr std::uint16_t kHomeLimit = 1U << 0;
inline constexpr std::uint16_t kEndLimit = 1U << 1;
inline constexpr std::uint16_t kEstop = 1U << 2;
inline constexpr std::uint16_t kDriveFault = 1U << 3;
inline constexpr std::uint16_t kWatchdogTripped = 1U << 4;
}  // namespace input_bit

// Holding registers (function 16): one write per loop cycle.
namespace holding {
inline constexpr int kDigitalOutputs = 0;  // u16 bit field
inline constexpr int kMotorVolts = 1;      // f32 armature voltage [V]
inline constexpr int kPumpCommand = 3;     // f32 pump drive [0..1]
inline constexpr int kWatchdogMs = 5;      // u16 outputs off after this silence [ms], 0 = off
inline constexpr int kCount = 6;
}  // namespace holding

namespace output_bit {
inline constexpr std::uint16_t kMotorEnable = 1U << 0;
inline constexpr std::uint16_t kCameraTrigger = 1U << 1;
}  // namespace output_bit

// Simulated rig only: its test panel (holding) and ground truth (input), from 100.
namespace sim_panel {
inline constexpr int kEstopButton = 100;       // u16 0/1
inline constexpr int kStuckForce = 101;        // u16 0/1
inline constexpr int kExtraForceN = 102;       // f32 [N]
inline constexpr int kLinkDrop = 104;          // u16 0/1: stop answering, drop connections
inline constexpr int kLateReplyUs = 105;       // u16 [us] delay before each reply
inline constexpr int kGarbageReplies = 106;    // u16 0/1: answer with invalid values
inline constexpr int kEndLimitForced = 107;    // u16 0/1
inline constexpr int kHomeLimitForced = 108;   // u16 0/1
inline constexpr int kNewEye = 109;            // u16 write 1: mount a fresh eye
inline constexpr int kDriveFault = 110;        // u16 0/1: the motor drive reports a fault
inline constexpr int kCarriageJammed = 111;    // u16 0/1: the lead screw seizes (stall)
inline constexpr int kPositionOffsetMm = 112;  // f32 [mm]: potentiometer reads this much further
inline constexpr int kHomeSwitchBroken = 114;  // u16 0/1: the home switch never closes
inline constexpr int kRejectWrites = 115;      // u16 0/1: output-block writes get exception 4
inline constexpr int kRestartDaq = 116;        // u16 write a new non-zero value: the DAQ reboots
inline constexpr int kTripWatchdog =
    117;  // u16 write a new non-zero value: the DAQ's watchdog trips
inline constexpr int kIopLeak =
    118;  // f32 [0..1]: fraction of the pump's pressure a leak loses (burst line)
inline constexpr int kCount = 20;
}  // namespace sim_panel

namespace sim_truth {
inline constexpr int kCarriageMm = 100;      // f32
inline constexpr int kForceN = 102;          // f32 true tissue force
inline constexpr int kMotorPowered = 104;    // u16 0/1
inline constexpr int kMotorOffTimeUs = 105;  // u32 accountable time [us] motor power last went off
inline constexpr int kSimTimeUs =
    107;  // u32 accountable time [us]: sim time less rig-sim's own stalls
inline constexpr int kTipDepthMm = 109;  // f32
inline constexpr int kMotorOffSilenceUs =
    111;  // u32 [us] the host's silence when motor power last went off (0xFFFFFFFF: never)
inline constexpr int kCount = 13;
}  // namespace sim_truth

inline constexpr int kMapSize = 120;  // registers of each table the server maps

inline void encode_u32(std::uint32_t value, std::uint16_t* words) {
  words[0] = static_cast<std::uint16_t>(value >> 16U);
  words[1] = static_cast<std::uint16_t>(value & 0xFFFFU);
}
inline std::uint32_t decode_u32(const std::uint16_t* words) {
  return (static_cast<std::uint32_t>(words[0]) << 16U) | words[1];
}
inline void encode_f32(float value, std::uint16_t* words) {
  encode_u32(std::bit_cast<std::uint32_t>(value), words);
}
inline float decode_f32(const std::uint16_t* words) {
  return std::bit_cast<float>(decode_u32(words));
}

}  // namespace rig::proto::daq
