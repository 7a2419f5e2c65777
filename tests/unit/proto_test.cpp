// API messages generated from proto/messages.json validate what comes in.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "rig/proto/messages.hpp"

namespace rig::proto {
namespace {

std::string field_at_fault(const std::string& body) {
  try {
    nlohmann::json::parse(body).get<RunRequest>();
  } catch (const ProtoError& e) {
    return e.field();
  }
  return "none";
}

TEST(Proto, AValidRunRequestParses) {
  const auto r =
      nlohmann::json::parse(
          R"({"eye_id":"E07","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14,"meta":{"temperature_C":"21"}})")
          .get<RunRequest>();
  EXPECT_EQ(r.eye_id, "E07");
  EXPECT_EQ(r.meta->at("temperature_C"), "21");
  EXPECT_FALSE(r.hold_s.has_value());
}

TEST(Proto, ErrorsNameTheFieldAtFault) {
  EXPECT_EQ(field_at_fault(R"({"iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14})"), "eye_id");
  EXPECT_EQ(field_at_fault(R"({"eye_id":"E","iop_mmHg":99,"velocity_mm_s":2,"depth_mm":14})"),
            "iop_mmHg");
  EXPECT_EQ(field_at_fault(R"({"eye_id":"E","iop_mmHg":15,"velocity_mm_s":"fast","depth_mm":14})"),
            "velocity_mm_s");
  EXPECT_EQ(field_at_fault(R"({"eye_id":"E 1;rm","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14})"),
            "eye_id");
  EXPECT_EQ(
      field_at_fault(R"({"eye_id":"E","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14,"speed":3})"),
      "speed");
  EXPECT_EQ(
      field_at_fault(
          R"({"eye_id":"E","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":14,"meta":{"Bad Key":"x"}})"),
      "meta.Bad Key");
}

TEST(Proto, NestedMessagesRoundTrip) {
  Status s;
  s.state = "Ready";
  s.interlocks.link_ok = true;
  s.loop.jitter_p99_us = 42.0;
  const Status back = nlohmann::json(s).get<Status>();
  EXPECT_EQ(back.state, "Ready");
  EXPECT_TRUE(back.interlocks.link_ok);
  EXPECT_DOUBLE_EQ(back.loop.jitter_p99_us, 42.0);
}

TEST(Proto, TheSchemaTextIsServedAsIs) {
  const auto schema = nlohmann::json::parse(messages_schema_json());
  EXPECT_EQ(schema["version"], kSchemaVersion);
  EXPECT_TRUE(schema["messages"].contains("RunRequest"));
}

}  // namespace
}  // namespace rig::proto
