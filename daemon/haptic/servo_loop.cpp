#include "servo_loop.hpp"

#include <algorithm>
#include <cmath>
#include <ctime>
#include <stdexcept>

namespace rig::haptic {

namespace {

std::int64_t now_ns() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * 1'000'000'000 + ts.tv_nsec;
}

double dot(const drivers::Vec3& a, const drivers::Vec3& b) noexcept {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

}  // namespace

ServoLoop::ServoLoop(const ServoSettings& settings, const ForceSource& source,
                     const drivers::HapticLimits& limits)
    : s_(settings),
      source_(&source),
      force_limit_N_(limits.max_continuous_force_N),
      estimator_(settings.position_resolution_mm, settings.output_latency_s),
      mesh_(settings.mesh) {
  const double norm = std::sqrt(dot(s_.axis, s_.axis));
  if (!(norm > 0.0)) throw std::invalid_argument("haptic: the keratome axis must not be zero");
  for (double& c : s_.axis) c /= norm;
  if (!(force_limit_N_ > 0.0))
    throw std::invalid_argument("haptic: the device reports no continuous force limit");
  if (!(s_.period_s > 0.0))
    throw std::invalid_argument("haptic: the servo period must be positive");
  if (s_.mesh.n > MeshSnapshot::kMaxPoints || s_.mesh.n < 3) {
    throw std::invalid_argument("haptic: mesh.n must be 3.." +
                                std::to_string(MeshSnapshot::kMaxPoints));
  }
}

void ServoLoop::device_fault(drivers::HapticFault fault) noexcept {
  counters_.fault.store(static_cast<std::uint8_t>(fault), std::memory_order_relaxed);
}

drivers::Vec3 ServoLoop::tick(const drivers::Vec3& position_mm, double t_s) noexcept {
  const std::int64_t start_ns = now_ns();
  if (!std::isfinite(position_mm[0]) || !std::isfinite(position_mm[1]) ||
      !std::isfinite(position_mm[2]) || !std::isfinite(t_s)) {
    counters_.nonfinite_positions.fetch_add(1, std::memory_order_relaxed);
    commanded_N_ = 0.0;
    return {0.0, 0.0, 0.0};
  }
  if (!started_) {
    started_ = true;
    t_start_s_ = t_last_s_ = t_s;
    last_start_ns_ = start_ns;
    surface_mm_ = s_.surface_mm.value_or(drivers::Vec3{
        position_mm[0] + s_.approach_mm * s_.axis[0], position_mm[1] + s_.approach_mm * s_.axis[1],
        position_mm[2] + s_.approach_mm * s_.axis[2]});
  }
  const drivers::Vec3 offset{position_mm[0] - surface_mm_[0], position_mm[1] - surface_mm_[1],
                             position_mm[2] - surface_mm_[2]};
  const double raw_depth = dot(offset, s_.axis);
  const double estimated = estimator_.update(raw_depth, t_s);
  const double depth = s_.estimate_between_counts ? estimated : raw_depth;
  const double axial = axial_force(depth, estimator_.velocity_mm_s(), t_s);
  drivers::Vec3 force{-s_.axis[0] * axial, -s_.axis[1] * axial,
                      -s_.axis[2] * axial};  // pushes the blade back out
  if (raw_depth > 0.0) {
    // In tissue the blade cannot move sideways: a spring back onto the axis, capped.
    drivers::Vec3 guide{};
    for (std::size_t i = 0; i < 3; ++i)
      guide[i] = -s_.guide_stiffness_N_per_mm * (offset[i] - raw_depth * s_.axis[i]);
    const double magnitude = std::sqrt(dot(guide, guide));
    const double scale = magnitude > force_limit_N_ ? force_limit_N_ / magnitude : 1.0;
    for (std::size_t i = 0; i < 3; ++i) force[i] += guide[i] * scale;
  }
  for (double& c : force) c = std::isfinite(c) ? c : 0.0;
  step_mesh(depth, axial, t_s);
  t_last_s_ = t_s;
  counters_.ticks.fetch_add(1, std::memory_order_relaxed);
  const std::int64_t end_ns = now_ns();
  tick_cost_.record(end_ns - start_ns);
  const auto period_ns = static_cast<std::int64_t>(s_.period_s * 1e9);
  if (end_ns - start_ns > period_ns) counters_.overruns.fetch_add(1, std::memory_order_relaxed);
  const std::int64_t gap_ns = start_ns - last_start_ns_;  // since the last tick began [ns]
  if (s_.count_late_ticks && gap_ns > period_ns * 3 / 2) {
    counters_.late_ticks.fetch_add(1, std::memory_order_relaxed);
  }
  if (gap_ns > counters_.longest_tick_gap_ns.load(std::memory_order_relaxed))
    counters_.longest_tick_gap_ns.store(gap_ns, std::memory_order_relaxed);  // one writer: this
  last_start_ns_ = start_ns;
  return force;
}

double ServoLoop::axial_force(double depth_mm, double velocity_mm_s, double t_s) noexcept {
  front_mm_ = std::max(front_mm_, depth_mm);
  double force = depth_mm > 0.0 || front_mm_ > 0.0
                     ? source_->force_N(depth_mm, front_mm_, velocity_mm_s)
                     : 0.0;
  if (!std::isfinite(force)) {
    counters_.nonfinite_forces.fetch_add(1, std::memory_order_relaxed);
    force = 0.0;
  }
  // Puncture: the force falls below 80 % of its peak beyond the peak's depth.
  if (force > peak_N_) peak_N_ = force, peak_depth_mm_ = depth_mm;
  if (!punctured_ && peak_N_ > 0.02 && force < 0.8 * peak_N_ && depth_mm > peak_depth_mm_)
    punctured_ = true;
  return make_safe(force, t_s);
}

double ServoLoop::make_safe(double force_N, double t_s) noexcept {
  const double ramp =
      s_.ramp_in_s > 0.0 ? std::clamp((t_s - t_start_s_) / s_.ramp_in_s, 0.0, 1.0) : 1.0;
  double force = force_N * ramp;
  if (std::abs(force) > force_limit_N_) {
    force = std::copysign(force_limit_N_, force);
    counters_.clamped_ticks.fetch_add(1, std::memory_order_relaxed);
  }
  const double dt = std::max(t_s - t_last_s_, s_.period_s);
  const double max_step = s_.max_slew_N_per_s * dt;
  if (std::abs(force - commanded_N_) > max_step) {
    force = commanded_N_ + std::copysign(max_step, force - commanded_N_);
    counters_.slew_limited_ticks.fetch_add(1, std::memory_order_relaxed);
  }
  commanded_N_ = force;
  return force;
}

void ServoLoop::step_mesh(double tip_depth_mm, double force_N, double t_s) noexcept {
  if (!s_.mesh_enabled) return;
  mesh_.step(std::max(t_s - t_last_s_, s_.period_s), tip_depth_mm, punctured_);
  if (counters_.ticks.load(std::memory_order_relaxed) %
          static_cast<std::uint64_t>(std::max(s_.mesh_publish_every_ticks, 1)) !=
      0) {
    return;
  }
  scratch_.sequence = ++mesh_sequence_;
  scratch_.t_s = t_s - t_start_s_;
  scratch_.tip_depth_mm = tip_depth_mm;
  scratch_.force_N = force_N;
  scratch_.punctured = punctured_;
  scratch_.point_count =
      mesh_.cross_section(scratch_.x_mm, scratch_.z_mm, MeshSnapshot::kMaxPoints);
  scratch_.grid_count = mesh_.positions(scratch_.grid_x_mm, scratch_.grid_y_mm, scratch_.grid_z_mm,
                                        MeshSnapshot::kMaxGridVertices);
  mesh_out_.publish(scratch_);
}

}  // namespace rig::haptic
