#pragma once
// A simulated camera for the simulated rig: renders the eye and the keratome from a scene
// callback (carriage position, corneal surface, puncture) at the configured frame rate,
// Mono8. The real cameras (Aravis, V4L2) implement the same interface.
#include <chrono>
#include <functional>
#include <vector>

#include "rig/drivers/camera.hpp"

namespace rig::drivers {

struct CameraScene {
  double carriage_mm = 0.0;
  double surface_mm = 20.0;
  double force_N = 0.0;
};

class SimCamera final : public Camera {
 public:
  SimCamera(const CameraSettings& settings, std::function<CameraScene()> scene);
  std::string describe() const override { return "simulated camera"; }
  IoStatus start() noexcept override;
  IoStatus stop() noexcept override;
  IoStatus trigger_software() noexcept override;
  IoStatus next_frame(FrameView& frame, int timeout_us) noexcept override;
  CameraCounters counters() const noexcept override { return counters_; }

 private:
  void render(const CameraScene& scene);

  CameraSettings settings_;
  std::function<CameraScene()> scene_;
  std::vector<std::uint8_t> pixels_;
  std::chrono::steady_clock::time_point next_;
  bool running_ = false;
  bool triggered_ = false;
  double deepest_mm_ = -1e9;
  CameraCounters counters_{};
};

}  // namespace rig::drivers
