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
#include <set>
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
  const std::string unit = std::regex_replace(unit_text(), std::regex("/usr/sbin/rigd"),
                                              std::string(RIG_TEST_BIN_DIR) + "/rigd");
  std::ofstream(dir.file("rigd.service")) << unit;
  const auto result =
      testing::run_command("systemd-analyze verify " + dir.file("rigd.service") + " 2>&1");
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output, "") << "systemd-analyze has remarks (it exits 0 even for unknown keys)";
}

TEST(SystemdUnit, AsksForNotifyWatchdogRealTimeADedicatedUserAndAReadOnlySystem) {
  const std::string unit = unit_text();
  for (const char* line : {"Type=notify", "WatchdogSec=", "LimitRTPRIO=", "LimitMEMLOCK=infinity",
                           "AmbientCapabilities=CAP_SYS_NICE", "User=rigd", "ProtectSystem=strict",
                           "StateDirectory=rigd", "ConfigurationDirectory=rigd",
                           "DevicePolicy=closed", "DeviceAllow=char-gpiochip rw"}) {
    EXPECT_NE(unit.find(line), std::string::npos) << "missing: " << line;
  }
}

std::string unit_with_this_build() {
  return std::regex_replace(unit_text(), std::regex("/usr/sbin/rigd"),
                            std::string(RIG_TEST_BIN_DIR) + "/rigd");
}

TEST(SystemdUnit, ItsSecurityExposureScoreIsAtMostThree) {
  ScratchDir dir("systemd-security");
  std::ofstream(dir.file("rigd.service")) << unit_with_this_build();
  const auto result =
      testing::run_command("systemd-analyze security --offline=true " + dir.file("rigd.service"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      result.output, m, std::regex(R"(Overall exposure level for rigd.service: ([0-9.]+))")))
      << result.output;
  const double exposure = std::stod(m[1].str());
  std::printf("systemd-analyze security: exposure %.1f\n", exposure);
  EXPECT_LE(exposure, 3.0) << result.output;
}

// The syscalls of a `systemd-analyze syscall-filter` group, nested groups expanded.
std::set<std::string> syscalls_of(const std::string& group, int depth = 0) {
  std::set<std::string> names;
  if (depth > 8) return names;
  const auto listed = testing::run_command("systemd-analyze syscall-filter " + group, false);
  std::istringstream lines(listed.output);
  std::string line;
  std::getline(lines, line);  // the group's own name
  while (std::getline(lines, line)) {
    const auto first = line.find_first_not_of(' ');
    if (first == std::string::npos || first < 4 || line[first] == '#') continue;
    const std::string name = line.substr(first);
    if (name[0] == '@') {
      const auto nested = syscalls_of(name, depth + 1);
      names.insert(nested.begin(), nested.end());
    } else {
      names.insert(name);
    }
  }
  return names;
}

// What the unit's SystemCallFilter= lines allow: the allow-list, less the ~deny-lists.
std::set<std::string> allowed_by_unit(const std::string& unit) {
  std::set<std::string> allowed;
  std::set<std::string> denied;
  std::istringstream lines(unit);
  std::string line;
  const std::string key = "SystemCallFilter=";
  while (std::getline(lines, line)) {
    if (line.rfind(key, 0) != 0) continue;
    std::string value = line.substr(key.size());
    const bool deny = !value.empty() && value[0] == '~';
    std::istringstream items(deny ? value.substr(1) : value);
    std::string item;
    while (items >> item) {
      const auto names = item[0] == '@' ? syscalls_of(item) : std::set<std::string>{item};
      (deny ? denied : allowed).insert(names.begin(), names.end());
    }
  }
  for (const auto& name : denied) allowed.erase(name);
  return allowed;
}

// rigd runs under strace with a seccomp filter that stops only on system calls the unit does
// NOT allow (so the RT loop keeps its pace): home, tare, a whole cut, SIGTERM. Any line in
// the trace is a call rigd would get EPERM for under systemd.
TEST(SystemdUnit, EverySystemCallRigdMakesWhileHomingAndCuttingPassesTheUnitsFilter) {
  const auto allowed = allowed_by_unit(unit_text());
  ASSERT_GT(allowed.size(), 100U);
  std::string pattern;
  for (const auto& name : allowed) pattern += (pattern.empty() ? "" : "|") + name;
  ScratchDir dir("systemd-syscalls");
  const std::string trace = dir.file("strace.log");
  {
    RigProcesses rig(dir, {}, {},
                     {"/usr/bin/strace", "-f", "-qq", "--seccomp-bpf", "-e",
                      "trace=!/^(" + pattern + ")$", "-o", trace});
    // How far it gets is not the subject here (a loaded machine may fault the loop under
    // ptrace); which system calls were made on the way is. Coverage is printed.
    rig.api().post("/api/home");
    rig.wait([](const nlohmann::json& s) { return s["state"] == "Ready" || s["state"] == "Fault"; },
             60);
    std::string reached = rig.status()["state"] == "Ready"
                              ? "homed"
                              : "not homed (" + rig.status().value("fault", std::string()) + ")";
    if (reached == "homed") {
      rig.api().post("/api/tare");
      rig.wait([](const nlohmann::json& s) { return s["tared"] == true; }, 10);
      rig.api().post("/api/run",
                     R"({"eye_id":"SECCOMP","iop_mmHg":15,"velocity_mm_s":4,"depth_mm":6})");
      reached += rig.wait_state("Done", 30)
                     ? ", cut to Done"
                     : ", cut ended in " + rig.status().value("state", std::string());
    }
    std::printf("traced rigd: started, %s, SIGTERM\n", reached.c_str());
    // rigd is strace's child: SIGTERM it, so its shutdown's system calls are traced too; it
    // must never outlive the test (strace, stopped, would leave it running).
    const auto child = testing::run_command("pgrep -P " + std::to_string(rig.rigd().pid()), false);
    const pid_t rigd_pid = child.output.empty() ? -1 : static_cast<pid_t>(std::stol(child.output));
    ASSERT_GT(rigd_pid, 0) << "no rigd under strace";
    ::kill(rigd_pid, SIGTERM);
    for (int i = 0; i < 100 && ::kill(rigd_pid, 0) == 0; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    if (::kill(rigd_pid, 0) == 0) ::kill(rigd_pid, SIGKILL);
    for (int i = 0; i < 50 && rig.rigd().running(); ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  std::ifstream log(trace);
  ASSERT_TRUE(log.good()) << "strace wrote no trace";
  std::string line, refused;
  const std::regex call(R"(^\d+\s+([a-z0-9_]+)\()");
  std::smatch m;
  while (std::getline(log, line)) {
    if (std::regex_search(line, m, call) && m[1].str() != "execve")
      refused += line + "\n";  // execve: strace starting rigd
  }
  EXPECT_EQ(refused, "") << "rigd would get EPERM under the unit's SystemCallFilter for:\n"
                         << refused;
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
  return static_cast<int>(
      std::count_if(messages.begin(), messages.end(),
                    [&](const std::string& m) { return m.find(needle) != std::string::npos; }));
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
  const auto ready = std::find_if(messages.begin(), messages.end(), [](const std::string& m) {
    return m.find("READY=1") != std::string::npos;
  });
  EXPECT_NE(ready->find("STATUS=RT loop at"), std::string::npos) << *ready;
  EXPECT_GE(count_containing(messages, "WATCHDOG=1"), 5) << "fed about 10 times a second";
  EXPECT_EQ(count_containing(messages, "STOPPING=1"), 1);
}

TEST(WatchdogFeeder, FeedsWhileTheLoopAdvancesAndStopsFeedingWhenItStalls) {
  std::atomic<bool> loop_running{true};
  std::atomic<int> feeds{0};
  std::atomic<int> reports{0};
  service::WatchdogFeeder feeder(
      std::chrono::milliseconds(20), [&] { return loop_running.load(); },
      [&] { feeds.fetch_add(1); },
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
  while (feeds.load() <= fed_before_stall_ended)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  feeder.stop();
}

}  // namespace
}  // namespace rig
