#pragma once
// The live rig: the force the load cell measures now (fed by a stream reader on another
// thread), felt whenever the hand's tip is past the corneal surface.
#include <atomic>

#include "force_source.hpp"

namespace rig::haptic {

class LiveForceSource final : public ForceSource {
 public:
  void update(double force_N) noexcept { force_.store(force_N, std::memory_order_relaxed); }
  double force_N(double depth_mm, double /*front_mm*/,
                 double /*velocity_mm_s*/) const noexcept override {
    return depth_mm > 0.0 ? force_.load(std::memory_order_relaxed) : 0.0;
  }
  const char* describe() const noexcept override { return "live rig"; }

 private:
  std::atomic<double> force_{0.0};
};

}  // namespace rig::haptic
