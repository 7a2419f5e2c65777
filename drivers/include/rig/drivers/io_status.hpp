#pragma once
// Result of one cyclic hardware call. Cyclic calls never throw (ros2_control's
// return_type, libfranka's narrow robot interface): the RT loop decides what a
// failure means for the run, the driver only reports it.
#include <cstdint>
#include <string_view>

namespace rig::drivers {

enum class IoStatus : std::uint8_t {
  kOk = 0,
  kTimeout,   // peer did not answer within the cycle budget (late or lost reply)
  kLinkDown,  // connection refused, reset or closed; device unplugged
  kBadData,   // answer arrived but failed validation (wrong length, CRC, garbage)
  kRefused,   // the device answered and explicitly refused (Modbus exception, USB error status)
  kStale,     // device answered with a sample it already delivered
  kNotReady,  // not configured / not started
};

constexpr std::string_view to_string(IoStatus status) noexcept {
  switch (status) {
    case IoStatus::kOk:
      return "ok";
    case IoStatus::kTimeout:
      return "timeout";
    case IoStatus::kLinkDown:
      return "link down";
    case IoStatus::kBadData:
      return "bad data";
    case IoStatus::kRefused:
      return "refused";
    case IoStatus::kStale:
      return "stale sample";
    case IoStatus::kNotReady:
      return "not ready";
  }
  return "unknown";
}

}  // namespace rig::drivers
