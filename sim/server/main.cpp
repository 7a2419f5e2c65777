// rig-sim: the simulated rig on loopback, speaking the DAQ's Modbus TCP register map.
#include <CLI/CLI.hpp>

#include <pthread.h>
#include <sched.h>
#include <atomic>

#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <fstream>
#include <iostream>
#include <thread>

#include "clock/cpu_wake_latency_request.hpp"
#include "clock/process_memory_lock.hpp"
#include "modbus_sim_server.hpp"
#include "rig/sim/hidden_effect.hpp"
#include "rig/sim/rig_physics.hpp"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int /*signal*/) {
  g_stop.store(true);
}

bool parse_effects(const std::vector<std::string>& specs,
                   std::vector<rig::sim::HiddenEffect>& effects) {
  for (const auto& spec : specs) {
    std::string error;
    const auto effect = rig::sim::parse_hidden_effect(spec, error);
    if (!effect) {
      std::cerr << "rig-sim: --effect " << error << "\n";
      return false;
    }
    effects.push_back(*effect);
  }
  return true;
}

// --cpu: every thread on that CPU (rig demo and the tests put rigd's loop there too, so a CPU
// the machine holds still stops the simulated DAQ and the loop together).
bool pin_to_cpu(int cpu) {
  if (cpu < 0) return true;
  cpu_set_t allowed;
  CPU_ZERO(&allowed);
  sched_getaffinity(0, sizeof allowed, &allowed);
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(cpu, &one);
  if (CPU_ISSET(cpu, &allowed) && sched_setaffinity(0, sizeof one, &one) == 0) return true;
  std::string cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c) {
    if (CPU_ISSET(c, &allowed)) cpus += (cpus.empty() ? "" : ",") + std::to_string(c);
  }
  std::cerr << "rig-sim: --cpu " << cpu << ": not a CPU this process may run on (" << cpus << ")\n";
  return false;
}

// A DAQ box answers at once: real-time priority (the physics thread started by run() inherits
// it), memory locked, and idle CPUs kept quick to wake (the request is held by the caller).
void answer_like_a_daq(int rt_priority, bool lock_memory, int cpu_wake_latency_us,
                       const rig::drivers::CpuWakeLatencyRequest& wake_latency) {
  if (rt_priority > 0) {
    sched_param param{};
    param.sched_priority = rt_priority;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0) {
      std::cerr << "rig-sim: warning: SCHED_FIFO refused, replies may be late under load\n";
    }
  }
  if (lock_memory) {
    const rig::drivers::ProcessMemoryLock memory = rig::drivers::lock_process_memory_in_ram();
    if (!memory.locked)
      std::cerr << "rig-sim: warning: mlockall refused (" << memory.error
                << "), page faults may delay replies\n";
  }
  if (cpu_wake_latency_us >= 0 && !wake_latency.held()) {
    std::cerr << "rig-sim: warning: " << wake_latency.why_not()
              << ": idle CPUs may wake late for requests\n";
  }
}

// rig-sim's command line.
struct SimCommandLine {
  rig::sim::SimServerOptions options;
  rig::sim::PhysicsParams physics;
  std::vector<std::string> effect_specs;
  std::string port_file;
  double covariate = 2.0;
  int rt_priority = 81;  // above every rigd loop (80): a DAQ answers whichever loop shares its CPU
  int cpu_wake_latency_us = 0;
  int cpu = -1;
  bool lock_memory = true;
};

void declare_options(CLI::App& app, SimCommandLine& c) {
  auto& options = c.options;
  auto& physics = c.physics;
  app.add_option("--bind", options.bind, "address to listen on (loopback by default)");
  app.add_option("--port", options.port, "TCP port, 0 = any free port")
      ->check(CLI::Range(0, 65535));
  app.add_option("--rtu", options.rtu_device,
                 "also serve Modbus RTU on this serial device (e.g. a socat pty)");
  app.add_option("--rtu-baud", options.rtu_baud, "RTU baud rate")->check(CLI::Range(1200, 4000000));
  app.add_option("--port-file", c.port_file, "write the port here once listening");
  app.add_option("--seed", physics.seed, "random seed (noise, per-eye variation)");
  app.add_option("--effect", c.effect_specs,
                 "hide an effect: name[:form][=size] or covariate:KEY[:form][=size]");
  app.add_option("--covariate-value", c.covariate,
                 "value of the hidden covariate for the mounted eyes");
  app.add_option("--surface-mm", physics.tissue.surface_mm,
                 "carriage position of the corneal surface [mm]");
  app.add_option("--eye-variability", physics.tissue.eye_variability,
                 "spread of the eyes: 1 = default (docs/sim.md), 0 = identical eyes");
  app.add_option("--force-noise-N", physics.sensors.force_noise_N, "load-cell noise, 1 sigma [N]");
  app.add_option(
      "--rt-priority", c.rt_priority,
      "SCHED_FIFO priority of the server and physics threads (a DAQ answers at once), 0 = none");
  app.add_option("--cpu", c.cpu,
                 "pin every thread to this CPU, -1 = any (rig demo and the tests pin rig-sim and "
                 "rigd's loop to one CPU: "
                 "a stalled CPU then stops both)")
      ->check(CLI::Range(-1, CPU_SETSIZE - 1));
  app.add_option(
         "--cpu-wake-latency-us", c.cpu_wake_latency_us,
         "PM QoS while serving: idle CPUs wake within this (0 = poll), -1 = no request [us]")
      ->check(CLI::Range(-1, 100000));
  app.add_option("--heartbeat-fd", options.heartbeat_fd,
                 "write a heartbeat line (CLOCK_MONOTONIC now and age of the last DAQ read [us]) "
                 "to this open descriptor, -1 = none")
      ->check(CLI::Range(-1, 1 << 20));
  app.add_option("--heartbeat-ms", options.heartbeat_ms, "heartbeat period [ms]")
      ->check(CLI::Range(1, 60000));
  app.add_flag("!--no-lock-memory", c.lock_memory,
               "do not mlockall (page faults may then delay replies)");
}

}  // namespace

static int run_rig_sim(int argc, char** argv) {
  CLI::App app{
      "rig-sim: simulated keratome rig (DC motor + lead screw, cornea, IOP line, DAQ) on Modbus "
      "TCP"};
  SimCommandLine c;
  declare_options(app, c);
  CLI11_PARSE(app, argc, argv);

  std::vector<rig::sim::HiddenEffect> effects;
  if (!parse_effects(c.effect_specs, effects)) return 2;
  if (!pin_to_cpu(c.cpu))
    return 2;  // before any thread starts: the physics thread inherits the mask
  try {
    rig::sim::RigPhysics rig(c.physics, effects);
    rig.set_next_eye_covariate(c.covariate);
    rig.mount_new_eye(c.covariate);
    rig::sim::ModbusSimServer server(rig, c.options);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    if (!c.port_file.empty()) std::ofstream(c.port_file) << server.port() << "\n";
    const rig::drivers::CpuWakeLatencyRequest wake_latency(c.cpu_wake_latency_us);
    answer_like_a_daq(c.rt_priority, c.lock_memory, c.cpu_wake_latency_us, wake_latency);
    if (!c.options.rtu_device.empty())
      std::cout << "rig-sim: Modbus RTU on " << c.options.rtu_device << std::endl;
    std::cout << "rig-sim: listening on " << c.options.bind << ":" << server.port() << std::endl;
    server.run(g_stop);
    std::cout << "rig-sim: reply time " << server.reply_time().summary() << "; gap between replies "
              << server.reply_gap().summary() << "; physics clock late "
              << server.physics_lateness().summary() << std::endl;
    if (server.heartbeat().enabled()) {
      std::cout << "rig-sim: heartbeat lines written " << server.heartbeat().written()
                << ", dropped " << server.heartbeat().dropped() << std::endl;
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}

// An exception no command caught (a bug, or a resource gone at setup) ends the program with its
// message and status 1, not with std::terminate's abort.
int main(int argc, char** argv) {
  try {
    return run_rig_sim(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rig-sim: error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "rig-sim: error: an unknown exception\n");
  }
  return 1;
}
