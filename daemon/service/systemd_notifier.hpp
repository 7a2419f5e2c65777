#pragma once
// rigd's side of systemd's notify protocol (sd_notify over $NOTIFY_SOCKET): READY=1 once
// the loop runs and the API listens, STATUS= in words, STOPPING=1 on shutdown, WATCHDOG=1
// from WatchdogFeeder. Without $NOTIFY_SOCKET (not under systemd) every call does nothing.
#include <chrono>
#include <string>

namespace rig::service {

class SystemdNotifier {
 public:
  void ready(const std::string& status) const;
  void status(const std::string& status) const;
  void stopping() const;
  void watchdog() const;
  // WatchdogSec= of the unit, 0 if systemd does not watch us.
  static std::chrono::microseconds watchdog_interval();

 private:
  static void send(const std::string& message);
};

}  // namespace rig::service
