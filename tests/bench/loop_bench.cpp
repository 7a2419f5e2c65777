// bench-loop: timing of rigd's RT loop at 1, 5 and 10 kHz against the simulated rig, next
// to cyclictest (rt-tests) measured on the same machine in the same session.
//   bench-loop [--seconds 30] [--rates 1000,5000,10000] [--mode modbus|inprocess|both]
// Figures: achieved rate, wake-up latency p50/p99/p99.9/max, overruns, DAQ misses.
#include <CLI/CLI.hpp>

#include <array>
#include <atomic>
#include <cstdio>
#include <iostream>
#include <memory>
#include <sstream>
#include <thread>

#include "child_process.hpp"
#include "clock/monotonic_clock.hpp"
#include "control_loop.hpp"
#include "modbus/modbus_daq.hpp"
#include "rig/sim/rig_physics.hpp"
#include "rt_thread.hpp"
#include "sim_daq.hpp"
#include "simulated_rig.hpp"
#include "wall_clock_sim_daq.hpp"

namespace {

struct Row {
  std::string mode;
  double rate_hz = 0, achieved_hz = 0, p50 = 0, p99 = 0, p999 = 0, max = 0;
  std::uint64_t overruns = 0, misses = 0;
};

Row run_loop(const std::string& mode, double rate_hz, double seconds, int priority,
             const std::string& sim_path) {
  std::unique_ptr<rig::cli::ChildProcess> sim;
  std::unique_ptr<rig::drivers::ModbusDaq> modbus;
  std::unique_ptr<rig::drivers::WallClockSimDaq> inprocess;
  rig::drivers::AnalogInput* analog = nullptr;
  rig::drivers::DigitalIo* digital = nullptr;
  rig::drivers::ActuatorDrive* drive = nullptr;
  if (mode == "modbus") {
    sim = std::make_unique<rig::cli::ChildProcess>(
        std::vector<std::string>{sim_path, "--port", "0"}, "/tmp/bench-loop-sim.log");
    const std::string line = sim->wait_for_line("listening on", 10000);
    rig::drivers::ModbusDaqSettings s;
    s.port = std::stoi(line.substr(line.rfind(':') + 1));
    s.response_timeout_us = static_cast<int>(0.7e6 / rate_hz);
    modbus = std::make_unique<rig::drivers::ModbusDaq>(s);
    analog = modbus.get();
    digital = modbus.get();
    drive = modbus.get();
  } else {
    inprocess = std::make_unique<rig::drivers::WallClockSimDaq>();
    analog = inprocess.get();
    digital = inprocess.get();
    drive = inprocess.get();
  }
  rig::drivers::MonotonicClock clock;
  rig::rt::LoopChannels channels;
  rig::rt::LoopSettings settings = rig::sim::loop_settings_for(rig::sim::PhysicsParams{});
  settings.rate_hz = rate_hz;
  rig::rt::ControlLoop loop(settings, {analog, digital, drive, &clock}, channels);
  std::atomic<bool> stop{false};
  rig::service::RtThreadReport report = rig::service::lock_process_memory(true);
  std::thread rt = rig::service::start_rt_thread(
      {priority, -1, true}, [&] { loop.run(stop); }, report);
  std::thread drain([&] {  // the stream ring's consumer, as in rigd
    rig::rt::Sample s;
    while (!stop.load()) {
      while (channels.stream.try_pop(s)) {
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  });
  std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
  stop.store(true);
  rt.join();
  drain.join();
  const auto snap = channels.jitter.snapshot();
  Row row{mode,
          rate_hz,
          static_cast<double>(channels.counters.cycles.load()) / seconds,
          snap.percentile_us(0.5),
          snap.percentile_us(0.99),
          snap.percentile_us(0.999),
          snap.max_ns / 1000.0,
          channels.counters.overruns.load(),
          channels.counters.io_misses.load()};
  if (!report.realtime) row.mode += " (no SCHED_FIFO)";
  return row;
}

// cyclictest -h prints a histogram "us count" per line: percentiles from it.
Row run_cyclictest(double rate_hz, double seconds, int priority) {
  const int interval_us = static_cast<int>(1e6 / rate_hz);
  const long loops = static_cast<long>(seconds * rate_hz);
  std::ostringstream cmd;
  cmd << "cyclictest -m -q -p " << priority << " -i " << interval_us << " -l " << loops
      << " -h 20000 2>/dev/null";
  Row row{"cyclictest", rate_hz, rate_hz};
  FILE* pipe = popen(cmd.str().c_str(), "r");
  if (pipe == nullptr) return row;
  std::vector<std::pair<double, double>> histogram;
  std::array<char, 512> line{};
  while (fgets(line.data(), line.size(), pipe) != nullptr) {
    double us = 0, count = 0;
    if (line[0] != '#' && std::sscanf(line.data(), "%lf %lf", &us, &count) == 2 && count > 0)
      histogram.emplace_back(us, count);
    std::string text(line.data());
    if (text.find("# Max Latencies:") == 0) row.max = std::stod(text.substr(16));
  }
  pclose(pipe);
  double total = 0;
  for (const auto& [us, c] : histogram) total += c;
  auto pct = [&](double f) {
    double seen = 0;
    for (const auto& [us, c] : histogram) {
      seen += c;
      if (seen >= f * total) return us;
    }
    return row.max;
  };
  if (total > 0) {
    row.p50 = pct(0.5);
    row.p99 = pct(0.99);
    row.p999 = pct(0.999);
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench-loop: RT loop timing on the simulated rig next to cyclictest"};
  double seconds = 30;
  std::vector<double> rates = {1000, 5000, 10000};
  std::string mode = "both";
  int priority = 80;
  std::string sim_path = std::string(RIG_BIN_DIR) + "/rig-sim";
  bool cyclictest = true;
  app.add_option("--seconds", seconds, "duration of each measurement [s]");
  app.add_option("--rates", rates, "loop rates [Hz]")->delimiter(',');
  app.add_option("--mode", mode, "modbus (rig-sim over TCP), inprocess, or both")
      ->check(CLI::IsMember({"modbus", "inprocess", "both"}));
  app.add_option("--priority", priority, "SCHED_FIFO priority");
  app.add_option("--sim", sim_path, "rig-sim executable");
  app.add_flag("!--no-cyclictest", cyclictest, "skip the cyclictest baseline");
  CLI11_PARSE(app, argc, argv);
  std::vector<Row> rows;
  for (const double rate : rates) {
    if (cyclictest) rows.push_back(run_cyclictest(rate, seconds, priority));
    if (mode != "modbus")
      rows.push_back(run_loop("rigd loop, in-process sim", rate, seconds, priority, sim_path));
    if (mode != "inprocess")
      rows.push_back(run_loop("rigd loop, rig-sim Modbus TCP", rate, seconds, priority, sim_path));
    const Row& r = rows.back();
    std::fprintf(stderr, "%s %.0f Hz done\n", r.mode.c_str(), rate);
  }
  std::printf("%-36s %8s %10s %8s %8s %9s %9s %9s %9s\n", "what", "rate_Hz", "achieved", "p50_us",
              "p99_us", "p99.9_us", "max_us", "overruns", "misses");
  for (const Row& r : rows) {
    std::printf("%-36s %8.0f %10.1f %8.1f %8.1f %9.1f %9.1f %9llu %9llu\n", r.mode.c_str(),
                r.rate_hz, r.achieved_hz, r.p50, r.p99, r.p999, r.max,
                static_cast<unsigned long long>(r.overruns),
                static_cast<unsigned long long>(r.misses));
  }
  std::printf(
      "(%.0f s each; wake-up latency = actual wake-up - deadline; cyclictest: -m -p %d, same "
      "machine, same session)\n",
      seconds, priority);
  return 0;
}
