#pragma once
// The simulated trainee's hand on the simulated Phantom: where the keratome tip really is
// along its axis, measured from the corneal surface [mm], at time t [s].
#include <atomic>
#include <vector>

namespace rig::drivers {

class VirtualHand {
 public:
  virtual ~VirtualHand() = default;
  virtual double depth_mm(double t_s) const noexcept = 0;
  virtual double duration_s() const noexcept = 0;
};

// From `start` outside the eye in, at constant velocity, to `depth`, a hold, and back.
class PushingHand final : public VirtualHand {
 public:
  PushingHand(double velocity_mm_s, double depth_mm, double start_mm = -1.0, double hold_s = 0.5);
  double depth_mm(double t_s) const noexcept override;
  double duration_s() const noexcept override;

 private:
  double v_, depth_, start_, hold_;
};

// Follows a recorded trajectory (a run's t and x), linearly interpolated.
class RecordedHand final : public VirtualHand {
 public:
  RecordedHand(std::vector<double> t_s, std::vector<double> x_mm);
  double depth_mm(double t_s) const noexcept override;
  double duration_s() const noexcept override { return t_.empty() ? 0.0 : t_.back(); }

 private:
  std::vector<double> t_, x_;
};

// Follows a position set from another thread (the live rig's blade), for up to `duration`.
class FollowingHand final : public VirtualHand {
 public:
  explicit FollowingHand(double duration_s) : duration_s_(duration_s) {}
  void set_depth(double depth_mm) noexcept { depth_.store(depth_mm, std::memory_order_relaxed); }
  double depth_mm(double /*t_s*/) const noexcept override {
    return depth_.load(std::memory_order_relaxed);
  }
  double duration_s() const noexcept override { return duration_s_; }

 private:
  double duration_s_;
  std::atomic<double> depth_{-1.0};
};

}  // namespace rig::drivers
