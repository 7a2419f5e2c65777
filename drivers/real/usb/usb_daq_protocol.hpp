#pragma once
// rigd's USB DAQ protocol, version 1 (docs/usb-daq-protocol.md is the firmware's spec).
// One request on the bulk OUT endpoint, one response on the bulk IN endpoint, each at
// most 64 bytes (one full-speed packet), little-endian. Every message starts with:
//   [0..1] magic "RD"  [2] version (1)  [3] opcode (response: opcode | 0x80)
//   [4..5] sequence (echoed)  [6] status (requests: 0)  [7] payload length [B]
// Pure encoding and validation here (no I/O), shared by the host driver, the simulated
// device and the fuzz target.
#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>

namespace rig::drivers::usbdaq {

inline constexpr std::uint8_t kVersion = 1;
inline constexpr std::size_t kHeaderSize = 8;
inline constexpr std::size_t kMaxMessage = 64;

enum class Opcode : std::uint8_t { kHello = 0x01, kReadInputs = 0x02, kWriteOutputs = 0x03 };
enum class Status : std::uint8_t { kOk = 0, kUnknownOpcode = 1, kBadLength = 2, kNotReady = 3 };

struct Header {
  Opcode opcode = Opcode::kHello;
  bool response = false;
  std::uint16_t sequence = 0;
  Status status = Status::kOk;
  std::uint8_t length = 0;  // payload bytes after the header
};

struct HelloReply {           // payload 8 B
  std::uint8_t channels = 3;  // analog inputs
  std::uint16_t firmware = 1;
  std::uint32_t conversion_hz = 1000;  // ADC conversions per second
};

struct InputsReply {           // payload 20 B
  std::uint32_t sequence = 0;  // conversion counter (stale detection)
  float force_volts = 0;       // [V]
  float position_volts = 0;    // [V]
  float iop_volts = 0;         // [V]
  std::uint16_t digital = 0;   // bit 0 home, 1 end, 2 e-stop, 3 drive fault
  std::uint16_t flags = 0;     // bit 0 watchdog tripped (outputs were forced off)
};

struct OutputsRequest {           // payload 12 B
  std::uint16_t digital = 0;      // bit 0 motor enable, bit 1 camera trigger
  std::uint16_t watchdog_ms = 0;  // outputs off after this much silence, 0 = never
  float motor_volts = 0;          // [V], + = into the eye
  float pump_command = 0;         // [0..1]
};

using Message = std::array<std::uint8_t, kMaxMessage>;

// Each encoder returns the message length [B].
std::size_t encode_request(Message& out, Opcode opcode, std::uint16_t sequence,
                           std::span<const std::uint8_t> payload = {});
std::size_t encode_response(Message& out, const Header& request, Status status,
                            std::span<const std::uint8_t> payload = {});
// Header of a well-formed message (magic, version, length fit the bytes), else nullopt.
std::optional<Header> decode_header(std::span<const std::uint8_t> bytes) noexcept;

std::array<std::uint8_t, 8> encode(const HelloReply& reply) noexcept;
std::array<std::uint8_t, 20> encode(const InputsReply& reply) noexcept;
std::array<std::uint8_t, 12> encode(const OutputsRequest& request) noexcept;
std::optional<HelloReply> decode_hello(std::span<const std::uint8_t> payload) noexcept;
std::optional<InputsReply> decode_inputs(std::span<const std::uint8_t> payload) noexcept;
std::optional<OutputsRequest> decode_outputs(std::span<const std::uint8_t> payload) noexcept;

}  // namespace rig::drivers::usbdaq
