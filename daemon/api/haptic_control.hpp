#pragma once
// Haptic playback behind the API (POST /api/haptic, GET /api/haptic, POST /api/haptic/stop).
#include <string>

#include "rig/proto/messages.hpp"

namespace rig::api {

class HapticControl {
 public:
  virtual ~HapticControl() = default;
  // Sets up and starts a session. Throws std::invalid_argument / std::runtime_error naming
  // what is wrong (400); returns false if a session is already running (409).
  virtual bool start(const proto::HapticRequest& request) = 0;
  virtual bool stop() = 0;  // false: nothing was running
  virtual proto::HapticStatus status() = 0;
};

}  // namespace rig::api
