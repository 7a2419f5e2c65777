// bench-gpio: e-stop edge to motor-enable off, through the GPIO driver and rigd's real
// control loop (SCHED_FIFO when allowed) on the simulated rig. The e-stop line is a
// simulated GPIO bank (same driver code above it as on gpio-sim); switches and analog come
// from the in-process physics on the wall clock. Each trial: home (motor powered), press
// the e-stop at a random moment, time until the motor-enable line drops, release, reset.
//   bench-gpio [--trials 60] [--rate 1000] [--priority 80]
// Figures: latency p50 / p90 / p99 / max [us], and how many stops came within one period.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <random>
#include <thread>
#include <vector>

#include "clock/monotonic_clock.hpp"
#include "control_loop.hpp"
#include "gpio/gpio_digital_io.hpp"
#include "rt_thread.hpp"
#include "sim_gpio_line_bank.hpp"
#include "simulated_rig.hpp"
#include "wall_clock_sim_daq.hpp"

namespace {

using namespace rig;

// Limit switches from the physics, e-stop and motor enable on the GPIO driver.
class EstopOnGpio final : public drivers::DigitalIo {
 public:
  EstopOnGpio(drivers::DigitalIo& switches, drivers::DigitalIo& gpio)
      : switches_(&switches), gpio_(&gpio) {}
  drivers::IoStatus read(drivers::DigitalInputs& in) noexcept override {
    drivers::DigitalInputs from_gpio;
    const drivers::IoStatus a = switches_->read(in);
    const drivers::IoStatus b = gpio_->read(from_gpio);
    in.estop = from_gpio.estop;
    return a != drivers::IoStatus::kOk ? a : b;
  }
  drivers::IoStatus write(const drivers::DigitalOutputs& out) noexcept override {
    switches_->write(out);
    return gpio_->write(out);
  }

 private:
  drivers::DigitalIo* switches_;
  drivers::DigitalIo* gpio_;
};

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5)];
}

bool wait_for(const std::function<bool()>& done, int timeout_ms) {
  for (int i = 0; i < timeout_ms * 10; ++i) {
    if (done()) return true;
    std::this_thread::sleep_for(std::chrono::microseconds(100));
  }
  return done();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"e-stop edge to motor-enable off through the GPIO driver and the RT loop"};
  int trials = 60, priority = 80;
  double rate_hz = 1000.0;
  app.add_option("--trials", trials, "e-stop presses")->check(CLI::Range(1, 10000));
  app.add_option("--rate", rate_hz, "loop rate [Hz]")->check(CLI::Range(50.0, 10000.0));
  app.add_option("--priority", priority, "SCHED_FIFO priority (0 = normal scheduling)");
  CLI11_PARSE(app, argc, argv);

  drivers::MonotonicClock clock;
  drivers::WallClockSimDaq daq;
  auto owned_bank = std::make_unique<drivers::SimGpioLineBank>();
  drivers::SimGpioLineBank& bank = *owned_bank;
  drivers::GpioDigitalIo gpio(std::move(owned_bank), false, 2'000'000, clock);
  EstopOnGpio digital(daq, gpio);
  rt::LoopSettings settings = sim::loop_settings_for(daq.physics().params());
  settings.rate_hz = rate_hz;
  rt::LoopChannels channels;
  rt::ControlLoop loop(settings, rt::LoopHardware{&daq, &digital, &daq, &clock}, channels);
  std::atomic<bool> stop{false};
  service::RtThreadReport report = service::lock_process_memory(priority > 0);
  std::thread rt_thread = service::start_rt_thread(
      {priority, -1, priority > 0}, [&] { loop.run(stop); }, report);
  for (const auto& w : report.warnings) std::printf("warning: %s\n", w.c_str());

  std::mt19937 rng(7);
  std::uniform_int_distribution<int> delay_us(2000, 20000);
  std::vector<double> latencies_us;
  std::uint64_t id = 1;
  int skipped = 0;
  for (int t = 0; t < trials; ++t) {
    channels.commands.push(rt::Command{rt::CommandKind::kHome, id++, {}});
    if (!wait_for([&] { return bank.output(drivers::kMotorEnableOutput); }, 2000)) {
      ++skipped;
      continue;
    }
    std::this_thread::sleep_for(
        std::chrono::microseconds(delay_us(rng)));  // a random phase of the loop
    if (!bank.output(drivers::kMotorEnableOutput)) {
      ++skipped;
      continue;
    }
    const std::int64_t pressed_ns = clock.now_ns();
    bank.set_input(drivers::kEstopInput, true, pressed_ns);
    if (!wait_for([&] { return !bank.output(drivers::kMotorEnableOutput); }, 1000)) {
      ++skipped;
      continue;
    }
    latencies_us.push_back(
        static_cast<double>(bank.output_changed_ns(drivers::kMotorEnableOutput) - pressed_ns) *
        1e-3);
    wait_for([&] { return channels.status.read().state == rt::RunState::kEStop; }, 1000);
    bank.set_input(drivers::kEstopInput, false, clock.now_ns());
    std::this_thread::sleep_for(std::chrono::milliseconds(5));  // > 2 ms debounce
    channels.commands.push(rt::Command{rt::CommandKind::kReset, id++, {}});
    wait_for([&] { return channels.status.read().state != rt::RunState::kEStop; }, 1000);
  }
  stop.store(true);
  rt_thread.join();
  const double period_us = 1e6 / rate_hz;
  const auto within = std::count_if(latencies_us.begin(), latencies_us.end(),
                                    [&](double v) { return v <= period_us; });
  std::printf("bench-gpio: loop %.0f Hz (period %.0f us, %s), %zu e-stop presses (%d skipped)\n",
              rate_hz, period_us, report.realtime ? "SCHED_FIFO" : "normal scheduling",
              latencies_us.size(), skipped);
  std::printf(
      "edge -> motor enable off [us]: p50 %.0f  p90 %.0f  p99 %.0f  max %.0f;  within one period: "
      "%ld/%zu\n",
      percentile(latencies_us, 0.5), percentile(latencies_us, 0.9), percentile(latencies_us, 0.99),
      percentile(latencies_us, 1.0), static_cast<long>(within), latencies_us.size());
  return latencies_us.empty() ? 1 : 0;
}
