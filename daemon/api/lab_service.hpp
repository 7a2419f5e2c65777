#pragma once
// The model lab behind the API (compare / diagnose / fit on archived runs). Work runs on
// its own worker thread: a long fit never holds the API's I/O thread.
#include <functional>
#include <string>

#include "rig/proto/messages.hpp"

namespace rig::api {

class LabService {
 public:
  using Done = std::function<void(int http_status, std::string json_body)>;
  virtual ~LabService() = default;
  // action: compare, diagnose or fit. `done` may be called from another thread.
  virtual void submit(const std::string& action, const proto::LabRequest& request, Done done) = 0;
};

}  // namespace rig::api
