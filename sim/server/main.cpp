// rig-sim: the simulated rig on loopback, speaking the DAQ's Modbus TCP register map.
#include <CLI/CLI.hpp>

#include <atomic>
#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fstream>
#include <iostream>
#include <thread>

#include "clock/cpu_wake_latency_request.hpp"
#include "modbus_sim_server.hpp"
#include "rig/sim/hidden_effect.hpp"
#include "rig/sim/rig_physics.hpp"

namespace {

std::atomic<bool> g_stop{false};
void on_signal(int /*signal*/) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rig-sim: simulated keratome rig (DC motor + lead screw, cornea, IOP line, DAQ) on Modbus TCP"};
  rig::sim::SimServerOptions options;
  rig::sim::PhysicsParams physics;
  std::vector<std::string> effect_specs;
  std::string port_file;
  double covariate = 2.0;
  int rt_priority = 70;
  int cpu_wake_latency_us = 0;
  int cpu = -1;
  bool lock_memory = true;
  app.add_option("--bind", options.bind, "address to listen on (loopback by default)");
  app.add_option("--port", options.port, "TCP port, 0 = any free port")->check(CLI::Range(0, 65535));
  app.add_option("--rtu", options.rtu_device, "also serve Modbus RTU on this serial device (e.g. a socat pty)");
  app.add_option("--rtu-baud", options.rtu_baud, "RTU baud rate")->check(CLI::Range(1200, 4000000));
  app.add_option("--port-file", port_file, "write the port here once listening");
  app.add_option("--seed", physics.seed, "random seed (noise, per-eye variation)");
  app.add_option("--effect", effect_specs, "hide an effect: name[:form][=size] or covariate:KEY[:form][=size]");
  app.add_option("--covariate-value", covariate, "value of the hidden covariate for the mounted eyes");
  app.add_option("--surface-mm", physics.tissue.surface_mm, "carriage position of the corneal surface [mm]");
  app.add_option("--eye-variability", physics.tissue.eye_variability, "spread of the eyes: 1 = default (docs/sim.md), 0 = identical eyes");
  app.add_option("--force-noise-N", physics.sensors.force_noise_N, "load-cell noise, 1 sigma [N]");
  app.add_option("--rt-priority", rt_priority, "SCHED_FIFO priority of the server and physics threads (a DAQ answers at once), 0 = none");
  app.add_option("--cpu", cpu,
                 "pin every thread to this CPU, -1 = any (rig demo and the tests pin rig-sim and rigd's loop to one CPU: "
                 "a stalled CPU then stops both)")->check(CLI::Range(-1, CPU_SETSIZE - 1));
  app.add_option("--cpu-wake-latency-us", cpu_wake_latency_us,
                 "PM QoS while serving: idle CPUs wake within this (0 = poll), -1 = no request [us]")->check(CLI::Range(-1, 100000));
  app.add_option("--heartbeat-fd", options.heartbeat_fd,
                 "write a heartbeat line (CLOCK_MONOTONIC now and age of the last DAQ read [us]) to this open descriptor, -1 = none")
      ->check(CLI::Range(-1, 1 << 20));
  app.add_option("--heartbeat-ms", options.heartbeat_ms, "heartbeat period [ms]")->check(CLI::Range(1, 60000));
  app.add_flag("!--no-lock-memory", lock_memory, "do not mlockall (page faults may then delay replies)");
  CLI11_PARSE(app, argc, argv);

  std::vector<rig::sim::HiddenEffect> effects;
  for (const auto& spec : effect_specs) {
    std::string error;
    const auto effect = rig::sim::parse_hidden_effect(spec, error);
    if (!effect) {
      std::cerr << "rig-sim: --effect " << error << "\n";
      return 2;
    }
    effects.push_back(*effect);
  }
  if (cpu >= 0) {  // before any thread starts: the physics thread inherits the mask
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    if (sched_setaffinity(0, sizeof one, &one) != 0) {
      std::cerr << "rig-sim: --cpu " << cpu << ": cannot run there (" << std::strerror(errno) << "; CPUs here: 0-"
                << std::thread::hardware_concurrency() - 1 << ")\n";
      return 2;
    }
  }
  try {
    rig::sim::RigPhysics rig(physics, effects);
    rig.set_next_eye_covariate(covariate);
    rig.mount_new_eye(covariate);
    rig::sim::ModbusSimServer server(rig, options);
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    if (!port_file.empty()) std::ofstream(port_file) << server.port() << "\n";
    // A DAQ box answers from its own CPU: real-time priority (the physics thread started by
    // run() inherits it), memory locked, and idle CPUs kept quick to wake.
    if (rt_priority > 0) {
      sched_param param{};
      param.sched_priority = rt_priority;
      if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &param) != 0) {
        std::cerr << "rig-sim: warning: SCHED_FIFO refused, replies may be late under load\n";
      }
    }
    if (lock_memory && mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
      std::cerr << "rig-sim: warning: mlockall refused, page faults may delay replies\n";
    }
    const rig::drivers::CpuWakeLatencyRequest wake_latency(cpu_wake_latency_us);
    if (cpu_wake_latency_us >= 0 && !wake_latency.held()) {
      std::cerr << "rig-sim: warning: " << wake_latency.why_not() << ": idle CPUs may wake late for requests\n";
    }
    if (!options.rtu_device.empty()) std::cout << "rig-sim: Modbus RTU on " << options.rtu_device << std::endl;
    std::cout << "rig-sim: listening on " << options.bind << ":" << server.port() << std::endl;
    server.run(g_stop);
    std::cout << "rig-sim: reply time " << server.reply_time().summary() << "; gap between replies "
              << server.reply_gap().summary() << "; physics clock late " << server.physics_lateness().summary()
              << std::endl;
    if (server.heartbeat().enabled()) {
      std::cout << "rig-sim: heartbeat lines written " << server.heartbeat().written() << ", dropped "
                << server.heartbeat().dropped() << std::endl;
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  return 0;
}
