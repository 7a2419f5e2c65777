// The load tier (label load, `./rig stress`; not part of `./rig test`): the demo's cut must
// never fault by accident on a busy 2-core machine. 50 demo cuts, two `rig demo --once` side
// by side at a time (as a parallel ctest runs two rigs), a headless browser on one of their
// pages, a CPU hog on every core and a disk writer. Counts the cuts that did not complete and
// prints why (LOAD-FIGURE lines; docs/loop-timing.md quotes them).
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <fstream>
#include <sstream>
#include <thread>

#include "busy_machine.hpp"
#include "child_process.hpp"
#include "cpu_stall_probe.hpp"
#include "test_paths.hpp"

namespace rig {
namespace {

using testing::ScratchDir;

int free_port() {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address);
  socklen_t length = sizeof address;
  getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length);
  close(fd);
  return ntohs(address.sin_port);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

struct Cut {
  bool completed = false;
  int retried = 0;   // timing faults the demo met and cut again after (its `accidental_faults`)
  std::string why;   // the demo's own words when it did not complete
  std::string loop;  // loop figures of a completed cut: jitter p99, overruns, DAQ misses
};

// One `rig demo --once` on its own ports and state; with a browser on its page during the cut.
Cut demo_cut(const ScratchDir& dir, const std::string& name, bool with_browser) {
  const int port = free_port();
  const std::string state = dir.file(name);
  const std::string log = dir.file(name + ".log");
  {
    cli::ChildProcess demo(
        {testing::bin("rig"), "demo", "--once", "--format", "json", "--port", std::to_string(port),
         "--sim", testing::bin("rig-sim"), "--rigd", testing::bin("rigd"), "--config",
         testing::source("config/rigd.sim.toml"), "--state-dir", state},
        log);
    std::unique_ptr<cli::ChildProcess> browser;
    const auto end = std::chrono::steady_clock::now() + std::chrono::minutes(5);
    while (demo.running() && std::chrono::steady_clock::now() < end) {
      if (with_browser && !browser &&
          read_file(state + "/rigd.log").find("ready, API on") != std::string::npos) {
        browser = testing::BusyMachine::browser_on_page(
            dir, "http://127.0.0.1:" + std::to_string(port) + "/", name);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  }
  const std::string out = read_file(log);
  Cut cut;
  const auto summary = out.find("{\"");
  if (summary != std::string::npos) {
    try {
      const auto j = nlohmann::json::parse(out.substr(summary, out.find('\n', summary) - summary));
      cut.completed = j["outcome"] == "completed";
      cut.retried = j.value("accidental_faults", -1);
      cut.loop = "jitter p99 " + std::to_string(j["loop_jitter_p99_us"].get<double>()) +
                 " us, overruns " + std::to_string(j["loop_overruns"].get<long>()) +
                 ", DAQ misses " + std::to_string(j["daq_misses"].get<long>());
    } catch (const std::exception& e) {
      cut.why = std::string("unreadable summary: ") + e.what();
    }
  }
  if (cut.completed &&
      cut.retried != 0) {  // completed, but only after a timing fault: still an accidental fault
    // The demo names the fault on the line before "a timing fault of the simulated rig".
    const auto marker = out.find("\n[demo] a timing fault");
    const auto start =
        marker == std::string::npos ? std::string::npos : out.rfind("[demo] ", marker);
    cut.why = "completed after " + std::to_string(cut.retried) + " accidental fault(s): " +
              (start != std::string::npos ? out.substr(start, marker - start)
                                          : std::string("(no fault line)"));
  } else if (!cut.completed && cut.why.empty()) {
    const auto failed = out.find("[demo] failed: ");
    cut.why = failed != std::string::npos ? out.substr(failed, out.find('\n', failed) - failed)
                                          : out.substr(out.size() > 400 ? out.size() - 400 : 0);
  }
  return cut;
}

TEST(LoadedDemo,
     FiftyCutsTwoSideBySideWithABrowserAndEveryCoreBusyCompleteWithoutAnAccidentalFault) {
  ScratchDir dir("loaded-demo");
  testing::BusyMachine busy(dir);
  testing::CpuStallProbe probe;  // what the machine itself did to time meanwhile
  constexpr int kRounds = 25;    // two cuts per round
  int completed = 0;
  std::vector<std::string> faults;
  for (int round = 0; round < kRounds; ++round) {
    Cut with_browser, beside;
    std::thread a([&] { with_browser = demo_cut(dir, "a" + std::to_string(round), true); });
    std::thread b([&] { beside = demo_cut(dir, "b" + std::to_string(round), false); });
    a.join();
    b.join();
    for (const Cut* cut : {&with_browser, &beside}) {
      if (cut->completed) ++completed;
      // A cut the demo had to make again after a timing fault counts: the fault happened.
      if (!cut->completed || cut->retried != 0)
        faults.push_back("round " + std::to_string(round) + ": " + cut->why);
    }
    const auto words = [](const Cut& c) { return c.completed && c.retried == 0 ? c.loop : c.why; };
    std::printf("LOAD-ROUND | %d | browser-side cut: %s | other cut: %s\n", round,
                words(with_browser).c_str(), words(beside).c_str());
    std::fflush(stdout);
  }
  std::printf("LOAD-FIGURE | loaded demo cuts %d | completed %d | accidental faults %zu\n",
              2 * kRounds, completed, faults.size());
  for (const auto& f : faults) std::printf("LOAD-FAULT | %s\n", f.c_str());
  probe.stop();
  std::printf("LOAD-STALLS | the machine held a CPU-pinned SCHED_FIFO 99 thread: %s\n",
              probe.summary(10.0).c_str());
  std::fflush(stdout);
  EXPECT_EQ(completed, 2 * kRounds);
  EXPECT_TRUE(faults.empty());
}

}  // namespace
}  // namespace rig
