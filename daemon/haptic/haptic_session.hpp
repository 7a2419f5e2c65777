#pragma once
// One haptic playback: a device, a force source, the servo and its stall watchdog. Setup
// (checks, thread start) throws with a clear message; once running, problems are counters
// and a fault in the report, and force goes to zero.
#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <string>

#include "force_source.hpp"
#include "mesh_snapshot.hpp"
#include "rig/drivers/haptic_device.hpp"
#include "servo_settings.hpp"

namespace rig::haptic {

class ServoLoop;

struct SessionReport {
  double wall_s = 0.0;
  double rate_hz = 0.0;  // ticks per wall second
  std::uint64_t ticks = 0;
  std::uint64_t overruns = 0;    // ticks longer than the period
  std::uint64_t late_ticks = 0;  // ticks started > 1.5 periods after the previous one
  std::uint64_t nonfinite_forces = 0;
  std::uint64_t clamped_ticks = 0;
  std::uint64_t slew_limited_ticks = 0;
  double tick_p50_us = 0.0, tick_p99_us = 0.0, tick_max_us = 0.0;  // servo tick cost
  bool watchdog_tripped = false;
  double longest_stall_ms = 0.0;     // the servo's silence as the stall watchdog saw it [ms]
  double longest_tick_gap_ms = 0.0;  // the longest time between tick starts, the servo's clock [ms]
  std::string fault;                 // empty: none
  double force_limit_N = 0.0;
  int mesh_vertices = 0, mesh_springs = 0;
};

// Refuses a source the device cannot render stably: its steepest rise (over 0.05 mm) must
// not exceed the device's nominal maximum stiffness. Throws std::invalid_argument.
void check_renderable(const ForceSource& source, const drivers::HapticLimits& limits);

class HapticSession {
 public:
  HapticSession(drivers::HapticDevice& device, const ForceSource& source, ServoSettings settings,
                std::chrono::milliseconds watchdog_timeout = std::chrono::milliseconds(20));
  ~HapticSession();
  // Runs until the device stops (a simulated hand's trajectory ends), *cancel turns true or
  // max_s [s] pass; hands each new mesh snapshot to on_mesh (on this thread, ~50 Hz).
  SessionReport run(const std::function<void(const MeshSnapshot&)>& on_mesh,
                    const std::atomic<bool>* cancel, double max_s);
  ServoLoop& servo() { return *servo_; }

 private:
  drivers::HapticDevice& device_;
  std::chrono::milliseconds watchdog_timeout_;
  std::unique_ptr<ServoLoop> servo_;
};

}  // namespace rig::haptic
