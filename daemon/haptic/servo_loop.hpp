#pragma once
// The haptic servo: called by the device once per tick (1 kHz) on its real-time thread.
// Position in, force out: project the stylus onto the keratome axis, estimate the tip
// between encoder counts, find contact with the corneal surface, ask the force source,
// then make it safe (NaN/inf guard, ramp-in, slew limit, clamp to the device's limits)
// and step the mass-spring cornea. No allocation, no locks, no I/O in tick(): the mesh
// and the status leave through triple buffers, the counters are relaxed atomics.
#include <atomic>
#include <cstdint>

#include "encoder_estimator.hpp"
#include "force_source.hpp"
#include "jitter_histogram.hpp"
#include "latest_value.hpp"
#include "mass_spring_cornea.hpp"
#include "mesh_snapshot.hpp"
#include "servo_settings.hpp"

namespace rig::haptic {

struct ServoCounters {
  std::atomic<std::uint64_t> ticks{0};
  std::atomic<std::uint64_t> nonfinite_forces{0};     // NaN/inf from the source, rendered as 0 N
  std::atomic<std::uint64_t> nonfinite_positions{0};  // NaN/inf from the device: 0 N, state kept
  std::atomic<std::uint64_t> clamped_ticks{0};        // force limited to the device's maximum
  std::atomic<std::uint64_t> slew_limited_ticks{0};
  std::atomic<std::uint64_t> overruns{0};    // tick took longer than the period
  std::atomic<std::uint64_t> late_ticks{0};  // tick started > 1.5 periods after the last
  // The longest time between two tick starts [ns], on the servo's own clock: how long the servo
  // itself was silent, which the stall watchdog judges from outside (tests compare the two).
  std::atomic<std::int64_t> longest_tick_gap_ns{0};
  std::atomic<std::uint8_t> fault{0};  // drivers::HapticFault reported by the device
};

class ServoLoop final : public drivers::HapticServo {
 public:
  // limits: as the device reports them. Allocates the mesh here, never in tick().
  ServoLoop(const ServoSettings& settings, const ForceSource& source,
            const drivers::HapticLimits& limits);

  drivers::Vec3 tick(const drivers::Vec3& position_mm, double t_s) noexcept override;
  void device_fault(drivers::HapticFault fault) noexcept override;

  const ServoCounters& counters() const { return counters_; }
  rt::JitterHistogram::Snapshot tick_cost() const { return tick_cost_.snapshot(); }  // [us] bins
  MeshSnapshot latest_mesh() { return mesh_out_.read(); }
  const MassSpringCornea& mesh() const { return mesh_; }  // after the device stopped
  double force_limit_N() const { return force_limit_N_; }

 private:
  double axial_force(double depth_mm, double velocity_mm_s, double t_s) noexcept;
  double make_safe(double force_N, double t_s) noexcept;
  void step_mesh(double tip_depth_mm, double force_N, double t_s) noexcept;

  ServoSettings s_;
  const ForceSource* source_;
  double force_limit_N_;
  EncoderEstimator estimator_;
  MassSpringCornea mesh_;
  bool started_ = false;
  drivers::Vec3 surface_mm_{};
  double t_start_s_ = 0.0, t_last_s_ = 0.0;
  std::int64_t last_start_ns_ = 0;
  double front_mm_ = -1e9;
  double commanded_N_ = 0.0;
  double peak_N_ = 0.0, peak_depth_mm_ = 0.0;
  bool punctured_ = false;
  std::uint64_t mesh_sequence_ = 0;
  MeshSnapshot scratch_{};  // filled in place, then copied into the triple buffer
  ServoCounters counters_;
  rt::JitterHistogram tick_cost_;
  rt::LatestValue<MeshSnapshot> mesh_out_;
};

}  // namespace rig::haptic
