#include "usb_daq_protocol.hpp"

#include <bit>
#include <cstring>

namespace rig::drivers::usbdaq {
namespace {

static_assert(std::endian::native == std::endian::little, "the wire format is little-endian");

class Writer {
 public:
  explicit Writer(std::span<std::uint8_t> out) : out_(out) {}
  void u8(std::uint8_t v) { out_[at_++] = v; }
  void u16(std::uint16_t v) {
    u8(static_cast<std::uint8_t>(v & 0xff));
    u8(static_cast<std::uint8_t>(v >> 8));
  }
  void u32(std::uint32_t v) {
    u16(static_cast<std::uint16_t>(v & 0xffff));
    u16(static_cast<std::uint16_t>(v >> 16));
  }
  void f32(float v) {
    u32(std::bit_cast<std::uint32_t>(v));
  }  // IEEE-754, little-endian words and bytes
 private:
  std::span<std::uint8_t> out_;
  std::size_t at_ = 0;
};

class Reader {
 public:
  explicit Reader(std::span<const std::uint8_t> in) : in_(in) {}
  std::uint8_t u8() { return in_[at_++]; }
  std::uint16_t u16() {
    const std::uint16_t lo = u8();
    return static_cast<std::uint16_t>(lo | (u8() << 8));
  }
  std::uint32_t u32() {
    const std::uint32_t lo = u16();
    return lo | (static_cast<std::uint32_t>(u16()) << 16);
  }
  float f32() { return std::bit_cast<float>(u32()); }

 private:
  std::span<const std::uint8_t> in_;
  std::size_t at_ = 0;
};

std::size_t encode_message(Message& out, std::uint8_t opcode, std::uint16_t sequence, Status status,
                           std::span<const std::uint8_t> payload) {
  const std::size_t length = std::min(payload.size(), kMaxMessage - kHeaderSize);
  Writer w(out);
  w.u8('R');
  w.u8('D');
  w.u8(kVersion);
  w.u8(opcode);
  w.u16(sequence);
  w.u8(static_cast<std::uint8_t>(status));
  w.u8(static_cast<std::uint8_t>(length));
  if (length > 0) std::memcpy(out.data() + kHeaderSize, payload.data(), length);
  return kHeaderSize + length;
}

}  // namespace

std::size_t encode_request(Message& out, Opcode opcode, std::uint16_t sequence,
                           std::span<const std::uint8_t> payload) {
  return encode_message(out, static_cast<std::uint8_t>(opcode), sequence, Status::kOk, payload);
}

std::size_t encode_response(Message& out, const Header& request, Status status,
                            std::span<const std::uint8_t> payload) {
  return encode_message(out,
                        static_cast<std::uint8_t>(static_cast<std::uint8_t>(request.opcode) | 0x80),
                        request.sequence, status, payload);
}

std::optional<Header> decode_header(std::span<const std::uint8_t> bytes) noexcept {
  if (bytes.size() < kHeaderSize || bytes.size() > kMaxMessage) return std::nullopt;
  if (bytes[0] != 'R' || bytes[1] != 'D' || bytes[2] != kVersion) return std::nullopt;
  Header h;
  h.response = (bytes[3] & 0x80) != 0;
  h.opcode = static_cast<Opcode>(bytes[3] & 0x7f);
  h.sequence = static_cast<std::uint16_t>(bytes[4] | (bytes[5] << 8));
  if (bytes[6] > static_cast<std::uint8_t>(Status::kNotReady)) return std::nullopt;
  h.status = static_cast<Status>(bytes[6]);
  h.length = bytes[7];
  if (kHeaderSize + h.length != bytes.size()) return std::nullopt;
  return h;
}

std::array<std::uint8_t, 8> encode(const HelloReply& reply) noexcept {
  std::array<std::uint8_t, 8> out{};
  Writer w(out);
  w.u8(reply.channels);
  w.u8(0);
  w.u16(reply.firmware);
  w.u32(reply.conversion_hz);
  return out;
}

std::array<std::uint8_t, 20> encode(const InputsReply& reply) noexcept {
  std::array<std::uint8_t, 20> out{};
  Writer w(out);
  w.u32(reply.sequence);
  w.f32(reply.force_volts);
  w.f32(reply.position_volts);
  w.f32(reply.iop_volts);
  w.u16(reply.digital);
  w.u16(reply.flags);
  return out;
}

std::array<std::uint8_t, 12> encode(const OutputsRequest& request) noexcept {
  std::array<std::uint8_t, 12> out{};
  Writer w(out);
  w.u16(request.digital);
  w.u16(request.watchdog_ms);
  w.f32(request.motor_volts);
  w.f32(request.pump_command);
  return out;
}

std::optional<HelloReply> decode_hello(std::span<const std::uint8_t> payload) noexcept {
  if (payload.size() != 8) return std::nullopt;
  Reader r(payload);
  HelloReply h;
  h.channels = r.u8();
  r.u8();
  h.firmware = r.u16();
  h.conversion_hz = r.u32();
  return h;
}

std::optional<InputsReply> decode_inputs(std::span<const std::uint8_t> payload) noexcept {
  if (payload.size() != 20) return std::nullopt;
  Reader r(payload);
  InputsReply in;
  in.sequence = r.u32();
  in.force_volts = r.f32();
  in.position_volts = r.f32();
  in.iop_volts = r.f32();
  in.digital = r.u16();
  in.flags = r.u16();
  return in;
}

std::optional<OutputsRequest> decode_outputs(std::span<const std::uint8_t> payload) noexcept {
  if (payload.size() != 12) return std::nullopt;
  Reader r(payload);
  OutputsRequest out;
  out.digital = r.u16();
  out.watchdog_ms = r.u16();
  out.motor_volts = r.f32();
  out.pump_command = r.f32();
  return out;
}

}  // namespace rig::drivers::usbdaq
