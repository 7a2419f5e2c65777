#include "systemd_notifier.hpp"

#include <systemd/sd-daemon.h>

namespace rig::service {

void SystemdNotifier::send(const std::string& message) {
  sd_notify(0, message.c_str());
}

void SystemdNotifier::ready(const std::string& status) const {
  send("READY=1\nSTATUS=" + status);
}
void SystemdNotifier::status(const std::string& status) const {
  send("STATUS=" + status);
}
void SystemdNotifier::stopping() const {
  send("STOPPING=1\nSTATUS=stopping: motor off, flushing the archive");
}
void SystemdNotifier::watchdog() const {
  send("WATCHDOG=1");
}

std::chrono::microseconds SystemdNotifier::watchdog_interval() {
  std::uint64_t usec = 0;
  return sd_watchdog_enabled(0, &usec) > 0 ? std::chrono::microseconds(usec)
                                           : std::chrono::microseconds(0);
}

}  // namespace rig::service
