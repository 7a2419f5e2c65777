// The USB DAQ protocol (docs/usb-daq-protocol.md) without a bus: the codec both ways, what
// a malformed message gets, and the simulated device's answers over the rig's physics.
// The driver over a real USB stack (FunctionFS gadget on dummy_hcd) is in tests/kernel.
#include <gtest/gtest.h>

#include <filesystem>

#include "usb/usb_daq.hpp"
#include "usb/usb_daq_protocol.hpp"
#include "usb_daq_device.hpp"

namespace rig::drivers {
namespace {

using usbdaq::Message;
using usbdaq::Opcode;
using usbdaq::Status;

std::span<const std::uint8_t> bytes(const Message& m, std::size_t n) {
  return {m.data(), n};
}

TEST(UsbDaqProtocol, ARequestRoundTripsThroughTheHeaderDecoder) {
  Message m{};
  const std::size_t n = usbdaq::encode_request(m, Opcode::kReadInputs, 0xBEEF);
  const auto h = usbdaq::decode_header(bytes(m, n));
  ASSERT_TRUE(h);
  EXPECT_EQ(h->opcode, Opcode::kReadInputs);
  EXPECT_FALSE(h->response);
  EXPECT_EQ(h->sequence, 0xBEEF);
  EXPECT_EQ(h->length, 0);
}

TEST(UsbDaqProtocol, InputsKeepEveryFieldAndFloatBitForBit) {
  usbdaq::InputsReply in{123456, 1.25F, -3.5F, 0.1F, 0x5, 1};
  const auto out = usbdaq::decode_inputs(usbdaq::encode(in));
  ASSERT_TRUE(out);
  EXPECT_EQ(out->sequence, 123456U);
  EXPECT_EQ(out->force_volts, 1.25F);
  EXPECT_EQ(out->position_volts, -3.5F);
  EXPECT_EQ(out->iop_volts, 0.1F);
  EXPECT_EQ(out->digital, 0x5);
  EXPECT_EQ(out->flags, 1);
}

TEST(UsbDaqProtocol, FloatsGoOnTheWireLittleEndianLowWordFirst) {
  usbdaq::OutputsRequest out{};
  out.motor_volts = 1.0F;  // 0x3F800000
  const auto wire = usbdaq::encode(out);
  EXPECT_EQ(wire[4], 0x00);
  EXPECT_EQ(wire[5], 0x00);
  EXPECT_EQ(wire[6], 0x80);
  EXPECT_EQ(wire[7], 0x3F);
}

TEST(UsbDaqProtocol, RejectsWrongMagicVersionLengthAndSize) {
  Message m{};
  const std::size_t n = usbdaq::encode_request(m, Opcode::kHello, 1);
  Message bad = m;
  bad[0] = 'X';
  EXPECT_FALSE(usbdaq::decode_header(bytes(bad, n)));
  bad = m;
  bad[2] = 9;
  EXPECT_FALSE(usbdaq::decode_header(bytes(bad, n)));
  bad = m;
  bad[7] = 4;  // claims a payload that is not there
  EXPECT_FALSE(usbdaq::decode_header(bytes(bad, n)));
  EXPECT_FALSE(usbdaq::decode_header(bytes(m, 3)));
  EXPECT_FALSE(usbdaq::decode_inputs(std::span<const std::uint8_t>(m.data(), 19)));
}

struct DeviceFixture : ::testing::Test {
  sim::RigPhysics physics{sim::PhysicsParams{}};
  sim::UsbDaqDevice device{physics};
  std::uint16_t sequence = 0;

  std::optional<usbdaq::Header> ask(Opcode op, std::span<const std::uint8_t> payload,
                                    Message& reply, double now_s) {
    Message request{};
    const std::size_t n = usbdaq::encode_request(request, op, ++sequence, payload);
    const std::size_t m = device.handle(bytes(request, n), reply, now_s);
    return usbdaq::decode_header(bytes(reply, m));
  }
};

TEST_F(DeviceFixture, AnswersHelloWithItsChannelsAndRate) {
  Message reply{};
  const auto h = ask(Opcode::kHello, {}, reply, 0.0);
  ASSERT_TRUE(h);
  EXPECT_TRUE(h->response);
  EXPECT_EQ(h->sequence, sequence);
  const auto hello =
      usbdaq::decode_hello(std::span<const std::uint8_t>(reply.data() + 8, h->length));
  ASSERT_TRUE(hello);
  EXPECT_EQ(hello->channels, 3);
  EXPECT_GT(hello->conversion_hz, 0U);
}

TEST_F(DeviceFixture, MovesTheCarriageWhenTheMotorIsEnabledAndDriven) {
  Message reply{};
  auto h = ask(Opcode::kReadInputs, {}, reply, 0.0);
  ASSERT_TRUE(h);
  const float before =
      usbdaq::decode_inputs(std::span<const std::uint8_t>(reply.data() + 8, h->length))
          ->position_volts;
  usbdaq::OutputsRequest out{1, 0, 6.0F, 0.0F};
  for (int i = 1; i <= 500; ++i)
    ASSERT_TRUE(ask(Opcode::kWriteOutputs, usbdaq::encode(out), reply, i * 1e-3));
  h = ask(Opcode::kReadInputs, {}, reply, 0.5);
  const auto after =
      usbdaq::decode_inputs(std::span<const std::uint8_t>(reply.data() + 8, h->length));
  ASSERT_TRUE(after);
  EXPECT_GT(std::abs(after->position_volts - before), 0.01F);
  EXPECT_TRUE(physics.truth().motor_powered);
}

TEST_F(DeviceFixture, DropsItsOutputsAndSaysSoWhenTheHostFallsSilent) {
  Message reply{};
  usbdaq::OutputsRequest out{1, 5, 3.0F, 0.0F};
  ask(Opcode::kWriteOutputs, usbdaq::encode(out), reply, 0.001);
  ASSERT_TRUE(physics.truth().motor_powered);
  const auto h = ask(Opcode::kReadInputs, {}, reply, 0.1);  // 100 ms of silence, watchdog 5 ms
  const auto in = usbdaq::decode_inputs(std::span<const std::uint8_t>(reply.data() + 8, h->length));
  ASSERT_TRUE(in);
  EXPECT_EQ(in->flags & 1, 1);
  EXPECT_FALSE(physics.truth().motor_powered);
}

TEST_F(DeviceFixture, AnswersAWrongLengthWithBadLengthAndGarbageWithNothing) {
  Message reply{};
  const std::array<std::uint8_t, 3> short_payload{1, 2, 3};
  const auto h = ask(Opcode::kWriteOutputs, short_payload, reply, 0.0);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->status, Status::kBadLength);
  const std::array<std::uint8_t, 5> garbage{9, 9, 9, 9, 9};
  EXPECT_EQ(device.handle(garbage, reply, 0.0), 0U);
}

TEST(UsbDaqSetup, AMissingDeviceIsAnErrorNamingItsIds) {
  UsbDaqSettings settings;
  settings.vendor_id = 0x1d6b;
  settings.product_id = 0x0104;
  settings.sysfs_root = std::filesystem::temp_directory_path() / "rig-no-usb-bus";  // an empty bus
  std::filesystem::create_directories(settings.sysfs_root);
  try {
    UsbDaq daq(settings);
    FAIL() << "opened a device that is not there";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("1d6b:0104"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("not found"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rig::drivers
