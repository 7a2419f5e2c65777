#include "haptic_session.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

#include "servo_loop.hpp"
#include "stall_watchdog.hpp"

namespace rig::haptic {

void check_renderable(const ForceSource& source, const drivers::HapticLimits& limits) {
  constexpr double kStep_mm = 0.01, kWindow_mm = 0.05, kDeepest_mm = 20.0;
  double steepest = 0.0, at = 0.0;
  for (double x = 0.0; x < kDeepest_mm; x += kStep_mm) {
    const double a = source.force_N(x, x, 2.0),
                 b = source.force_N(x + kWindow_mm, x + kWindow_mm, 2.0);
    if (!std::isfinite(a) || !std::isfinite(b)) continue;  // the servo guards these per tick
    const double slope = (b - a) / kWindow_mm;
    if (slope > steepest) steepest = slope, at = x;
  }
  if (steepest > limits.max_stiffness_N_per_mm) {
    char text[200];
    std::snprintf(
        text, sizeof text,
        "haptic: the %s rises %.2f N/mm at %.2f mm, more than the device's nominal maximum "
        "stiffness %.2f N/mm (HD_NOMINAL_MAX_STIFFNESS)",
        source.describe(), steepest, at, limits.max_stiffness_N_per_mm);
    throw std::invalid_argument(text);
  }
}

HapticSession::HapticSession(drivers::HapticDevice& device, const ForceSource& source,
                             ServoSettings settings, std::chrono::milliseconds watchdog_timeout)
    : device_(device), watchdog_timeout_(watchdog_timeout) {
  const drivers::HapticLimits limits = device.limits();
  check_renderable(source, limits);
  settings.period_s = device.period_s();
  settings.output_latency_s = device.output_latency_s();
  // On a virtual clock wall-time gaps between ticks mean nothing: they are not late ticks.
  if (!device.paced_by_wall_clock()) settings.count_late_ticks = false;
  servo_ = std::make_unique<ServoLoop>(settings, source, limits);
}

HapticSession::~HapticSession() {
  device_.stop();
}

SessionReport HapticSession::run(const std::function<void(const MeshSnapshot&)>& on_mesh,
                                 const std::atomic<bool>* cancel, double max_s) {
  using Clock = std::chrono::steady_clock;
  // The watchdog guards a hand on a device in real time. On virtual time the servo runs as fast
  // as the CPU allows and a loaded machine's stalls endanger no one: off (0 ms).
  StallWatchdog watchdog(
      device_, device_.paced_by_wall_clock() ? watchdog_timeout_ : std::chrono::milliseconds(0));
  const Clock::time_point start = Clock::now();
  device_.start(*servo_);
  watchdog.start();
  std::uint64_t last_sequence = 0;
  auto seconds = [&start] { return std::chrono::duration<double>(Clock::now() - start).count(); };
  auto keep_going = [&] {
    return device_.running() && seconds() < max_s && (cancel == nullptr || !cancel->load()) &&
           !watchdog.tripped() && servo_->counters().fault.load() == 0;
  };
  while (keep_going()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    if (!on_mesh) continue;
    const MeshSnapshot mesh = servo_->latest_mesh();
    if (mesh.sequence != last_sequence) {
      last_sequence = mesh.sequence;
      on_mesh(mesh);
    }
  }
  device_.stop();
  watchdog.stop();
  SessionReport r;
  r.wall_s = seconds();
  const ServoCounters& c = servo_->counters();
  r.ticks = c.ticks.load();
  r.rate_hz = r.wall_s > 0.0 ? static_cast<double>(r.ticks) / r.wall_s : 0.0;
  r.overruns = c.overruns.load();
  r.late_ticks = c.late_ticks.load();
  r.nonfinite_forces = c.nonfinite_forces.load();
  r.clamped_ticks = c.clamped_ticks.load();
  r.slew_limited_ticks = c.slew_limited_ticks.load();
  const auto cost = servo_->tick_cost();
  r.tick_p50_us = cost.percentile_us(0.5);
  r.tick_p99_us = cost.percentile_us(0.99);
  r.tick_max_us = static_cast<double>(cost.max_ns) / 1000.0;
  r.watchdog_tripped = watchdog.tripped();
  r.longest_stall_ms = watchdog.longest_gap_ms();
  r.longest_tick_gap_ms = static_cast<double>(c.longest_tick_gap_ns.load()) / 1e6;
  const auto fault = static_cast<drivers::HapticFault>(c.fault.load());
  if (fault != drivers::HapticFault::kNone) r.fault = drivers::to_string(fault);
  if (r.watchdog_tripped && r.fault.empty())
    r.fault = "servo stalled: the watchdog turned force off";
  r.force_limit_N = servo_->force_limit_N();
  r.mesh_vertices = servo_->mesh().vertex_count();
  r.mesh_springs = servo_->mesh().spring_count();
  return r;
}

}  // namespace rig::haptic
