// rigd under systemd: the unit passes `systemd-analyze verify` without a word, asks for
// what a lab PC needs, and rigd speaks the notify protocol (READY, STATUS, WATCHDOG,
// STOPPING) to a $NOTIFY_SOCKET this test listens on. The watchdog is fed only while the
// RT loop runs.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <regex>
#include <sstream>
#include <thread>

#include "command.hpp"
#include "rig_processes.hpp"
#include "test_paths.hpp"
#include "watchdog_feeder.hpp"

namespace rig {
namespace {

using testing::RigProcesses;
using testing::ScratchDir;

std::string unit_text() {
  std::ifstream in(std::string(RIG_SOURCE_DIR) + "/systemd/rigd.service");
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(SystemdUnit, PassesSystemdAnalyzeVerifyWithoutAWord) {
  ScratchDir dir("systemd-verify");
  // verify insists that ExecStart= exists: point it at this build's rigd.
  const std::string unit = std::regex_replace(unit_text(), std::regex("/usr/sbin/rigd"), std::string(RIG_TEST_BIN_DIR) + "/rigd");
  std::ofstream(dir.file("rigd.service")) << unit;
  const auto result = testing::run_command("systemd-analyze verify " + dir.file("rigd.service") + " 2>&1");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "") << "systemd-analyze has remarks (it exits 0 even for unknown keys)";
}

TEST(SystemdUnit, AsksForNotifyWatchdogRealTimeADedicatedUserAndAReadOnlySystem) {
  const std::string unit = unit_text();
  for (const char* line : {"Type=notify", "WatchdogSec=", "LimitRTPRIO=", "LimitMEMLOCK=infinity",
                           "AmbientCapabilities=CAP_SYS_NICE", "User=rigd", "ProtectSystem=strict", "StateDirectory=rigd",
                           "ConfigurationDirectory=rigd", "DevicePolicy=closed", "DeviceAllow=char-gpiochip rw"}) {
    EXPECT_NE(unit.find(line), std::string::npos) << "missing: " << line;
  }
}

// A datagram socket standing in for systemd's notify socket.
class NotifySocket {
 public:
  explicit NotifySocket(const std::string& path) : path_(path) {
    fd_ = ::socket(AF_UNIX, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_un addr{};
    addr.sun_family = AF_UNIX;
    path.copy(addr.sun_path, sizeof addr.sun_path - 1);
    ::unlink(path.c_str());
    bound_ = ::bind(fd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    timeval timeout{0, 200'000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
  }
  ~NotifySocket() {
    ::close(fd_);
    ::unlink(path_.c_str());
  }
  bool bound() const { return bound_; }
  // Messages received within `seconds`, each as sent.
  std::vector<std::string> receive_for(double seconds) {
    std::vector<std::string> messages;
    const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    char buffer[4096];
    while (std::chrono::steady_clock::now() < end) {
      const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
      if (n > 0) messages.emplace_back(buffer, static_cast<std::size_t>(n));
    }
    return messages;
  }

 private:
  std::string path_;
  int fd_ = -1;
  bool bound_ = false;
};

int count_containing(const std::vector<std::string>& messages, const std::string& needle) {
  return static_cast<int>(std::count_if(messages.begin(), messages.end(), [&](const std::string& m) { return m.find(needle) != std::string::npos; }));
}

TEST(SystemdNotify, RigdSaysReadyFeedsTheWatchdogWhileItsLoopRunsAndSaysStopping) {
  ScratchDir dir("systemd-notify");
  NotifySocket notify(dir.file("notify.sock"));
  ASSERT_TRUE(notify.bound());
  ::setenv("NOTIFY_SOCKET", dir.file("notify.sock").c_str(), 1);
  ::setenv("WATCHDOG_USEC", "200000", 1);  // WatchdogSec=0.2 s: fed every 0.1 s
  std::vector<std::string> messages;
  {
    RigProcesses rig(dir);
    ::unsetenv("NOTIFY_SOCKET");
    ::unsetenv("WATCHDOG_USEC");
    messages = notify.receive_for(1.0);
    ::kill(rig.rigd().pid(), SIGTERM);
    const auto after = notify.receive_for(1.0);
    messages.insert(messages.end(), after.begin(), after.end());
  }
  ASSERT_GE(count_containing(messages, "READY=1"), 1) << "no READY=1";
  const auto ready = std::find_if(messages.begin(), messages.end(), [](const std::string& m) { return m.find("READY=1") != std::string::npos; });
  EXPECT_NE(ready->find("STATUS=RT loop at"), std::string::npos) << *ready;
  EXPECT_GE(count_containing(messages, "WATCHDOG=1"), 5) << "fed about 10 times a second";
  EXPECT_EQ(count_containing(messages, "STOPPING=1"), 1);
}

TEST(WatchdogFeeder, FeedsWhileTheLoopAdvancesAndStopsFeedingWhenItStalls) {
  std::atomic<bool> loop_running{true};
  std::atomic<int> feeds{0};
  std::atomic<int> reports{0};
  service::WatchdogFeeder feeder(
      std::chrono::milliseconds(20), [&] { return loop_running.load(); }, [&] { feeds.fetch_add(1); },
      [&](const std::string& text) {
        EXPECT_NE(text.find("stalled"), std::string::npos);
        reports.fetch_add(1);
      });
  feeder.start();
  while (feeds.load() < 5) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  loop_running.store(false);
  while (feeder.missed() < 5) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  const int fed_before_stall_ended = feeds.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_LE(feeds.load(), fed_before_stall_ended) << "fed while the loop was stalled";
  EXPECT_EQ(reports.load(), 1) << "one report per stall, not one per period";
  loop_running.store(true);
  while (feeds.load() <= fed_before_stall_ended) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  feeder.stop();
}

}  // namespace
}  // namespace rig
