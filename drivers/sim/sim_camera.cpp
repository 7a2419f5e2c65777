#include "sim_camera.hpp"

#include <algorithm>
#include <cmath>
#include <thread>

namespace rig::drivers {

SimCamera::SimCamera(const CameraSettings& settings, std::function<CameraScene()> scene)
    : settings_(settings),
      scene_(std::move(scene)),
      pixels_(static_cast<std::size_t>(settings.width * settings.height), 0) {}

IoStatus SimCamera::start() noexcept {
  running_ = true;
  next_ = std::chrono::steady_clock::now();
  return IoStatus::kOk;
}

IoStatus SimCamera::stop() noexcept {
  running_ = false;
  return IoStatus::kOk;
}

IoStatus SimCamera::trigger_software() noexcept {
  triggered_ = true;
  return IoStatus::kOk;
}

void SimCamera::render(const CameraScene& scene) {
  const int w = settings_.width, h = settings_.height;
  const double px_per_mm = w / 32.0;  // 32 mm across the image
  const double depth = scene.carriage_mm - scene.surface_mm;
  deepest_mm_ = depth < -1.0 ? -1e9 : std::max(deepest_mm_, depth);
  const bool cut = deepest_mm_ > 3.5;  // the blade went through
  const double apex_x = w * 0.4 + (cut ? 0.0 : std::clamp(depth, 0.0, 3.5) * px_per_mm * 0.6);
  const double radius = h * 0.9;
  const double cx = w * 0.4 + radius, cy = h * 0.5;
  const double tip_x = w * 0.4 + depth * px_per_mm;
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const double dx = x - cx, dy = y - cy;
      const double r = std::sqrt(dx * dx + dy * dy);
      const double indented = r - (cx - apex_x) + std::abs(dy) * 0.02;
      std::uint8_t v = 30;
      if (indented < 0.0) v = 150;                                  // the eye
      if (std::abs(indented) < 2.0) v = 230;                        // the cornea
      const double half_width = std::max(0.0, (tip_x - x) * 0.18);  // the blade, a wedge
      if (x <= tip_x && std::abs(y - cy) <= half_width && x > tip_x - 14.0 * px_per_mm) v = 245;
      if (cut && x > w * 0.4 && x < w * 0.4 + deepest_mm_ * px_per_mm && std::abs(y - cy) < 1.5 &&
          x > tip_x)
        v = 10;
      pixels_[static_cast<std::size_t>(y) * static_cast<std::size_t>(w) +
              static_cast<std::size_t>(x)] = v;
    }
  }
}

IoStatus SimCamera::next_frame(FrameView& frame, int timeout_us) noexcept {
  if (!running_) return IoStatus::kNotReady;
  const auto period = std::chrono::duration<double>(1.0 / std::max(settings_.frame_rate_hz, 0.1));
  next_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
  if (const auto late = std::chrono::steady_clock::now() - next_; late > period) {
    // A real camera does not deliver frames its reader was too slow for: they are lost.
    const auto missed = static_cast<std::uint64_t>(late / period);
    counters_.dropped += missed;
    next_ += std::chrono::duration_cast<std::chrono::steady_clock::duration>(
        period * static_cast<double>(missed));
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::microseconds(timeout_us);
  if (next_ > deadline) {
    std::this_thread::sleep_until(deadline);
    next_ -= std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    return IoStatus::kTimeout;
  }
  std::this_thread::sleep_until(next_);
  render(scene_());
  const auto now = std::chrono::steady_clock::now().time_since_epoch();
  frame.pixels = pixels_;
  frame.width = settings_.width;
  frame.height = settings_.height;
  frame.format = PixelFormat::kMono8;
  frame.host_timestamp_ns =
      static_cast<std::uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(now).count());
  frame.camera_timestamp_ns = frame.host_timestamp_ns;
  frame.frame_id = ++counters_.frames;
  return IoStatus::kOk;
}

}  // namespace rig::drivers
