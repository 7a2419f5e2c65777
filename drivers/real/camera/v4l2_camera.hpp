#pragma once
// UVC (and any V4L2 capture) camera: memory-mapped streaming, format negotiation, frame
// rate through VIDIOC_S_PARM, frames time-stamped by the kernel (CLOCK_MONOTONIC, the
// host clock the loop runs on) and by their arrival. UVC has no software trigger: use the
// free-running stream (frames tied to samples by time) or a camera wired to the GPIO
// trigger line. The file descriptor and every mapping are owned by RAII members; errno
// becomes IoStatus in one place.
#include <cstdint>
#include <string>
#include <vector>

#include "rig/drivers/camera.hpp"

namespace rig::drivers {

class V4l2Camera final : public Camera {
 public:
  // Opens the device and negotiates format, size and rate; throws naming the device and
  // what it refused (setup only). The negotiated values are in describe() and format().
  V4l2Camera(const std::string& device, const CameraSettings& settings);
  ~V4l2Camera() override;
  V4l2Camera(const V4l2Camera&) = delete;
  V4l2Camera& operator=(const V4l2Camera&) = delete;

  std::string describe() const override { return description_; }
  IoStatus start() noexcept override;
  IoStatus stop() noexcept override;
  IoStatus trigger_software() noexcept override { return IoStatus::kNotReady; }
  IoStatus next_frame(FrameView& frame, int timeout_us) noexcept override;
  CameraCounters counters() const noexcept override { return counters_; }

  int width() const noexcept { return width_; }
  int height() const noexcept { return height_; }
  PixelFormat format() const noexcept { return format_; }
  double frame_rate_hz() const noexcept { return frame_rate_hz_; }
  // Whether buffer timestamps are on CLOCK_MONOTONIC (then camera time = host time).
  bool monotonic_timestamps() const noexcept { return monotonic_timestamps_; }

 private:
  struct Mapping {
    void* address = nullptr;
    std::size_t length = 0;
  };
  void negotiate_format(const CameraSettings& settings);
  void set_frame_rate(double hz);
  void map_buffers(int count);
  void unmap_buffers() noexcept;
  IoStatus requeue_lent() noexcept;

  std::string device_, description_;
  int fd_ = -1;
  std::vector<Mapping> buffers_;
  int lent_ = -1;  // index of the buffer behind the last FrameView
  bool streaming_ = false;
  bool monotonic_timestamps_ = false;
  int width_ = 0, height_ = 0;
  PixelFormat format_ = PixelFormat::kMono8;
  double frame_rate_hz_ = 0.0;
  std::int64_t last_sequence_ = -1;
  CameraCounters counters_{};
};

}  // namespace rig::drivers
