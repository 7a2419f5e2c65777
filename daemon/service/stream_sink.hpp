#pragma once
// Where live stream messages go (WebSocket clients, UDP). publish() is called from the
// stream hub's thread and must not block: sinks queue and drop, never wait.
#include <memory>
#include <string>

namespace rig::service {

class StreamSink {
 public:
  virtual ~StreamSink() = default;
  virtual void publish(std::shared_ptr<const std::string> message) = 0;
};

}  // namespace rig::service
