#pragma once
// Cameras (GigE Vision via Aravis, UVC via V4L2, simulated). Never called from the RT
// loop: a camera thread pulls frames and hands them to the recorder and the page.
#include <cstdint>
#include <span>
#include <string>

#include "rig/drivers/io_status.hpp"

namespace rig::drivers {

enum class PixelFormat : std::uint8_t { kMono8, kRgb8, kYuyv };

struct CameraSettings {
  int width = 640;   // [px]
  int height = 480;  // [px]
  int offset_x = 0;  // ROI origin [px]
  int offset_y = 0;
  double exposure_us = 1000.0;    // [us]
  double frame_rate_hz = 30.0;    // free-run rate when not triggered [Hz]
  bool hardware_trigger = false;  // exposure on the GPIO trigger line
  bool software_trigger = false;  // exposure on trigger_software()
  int packet_size = 1400;         // GigE stream packet size [B]
  int buffer_count = 16;          // frames in the pool
  PixelFormat pixel_format = PixelFormat::kMono8;
};

struct FrameView {
  std::span<const std::uint8_t> pixels;
  int width = 0;
  int height = 0;
  PixelFormat format = PixelFormat::kMono8;
  std::uint64_t camera_timestamp_ns = 0;  // camera's own tick, converted to ns
  std::uint64_t host_timestamp_ns = 0;    // CLOCK_MONOTONIC when the frame arrived
  std::uint64_t frame_id = 0;             // camera's frame/block id
};

struct CameraCounters {
  std::uint64_t frames = 0;
  std::uint64_t dropped = 0;  // buffers lost or incomplete
  std::uint64_t missing_packets = 0;
  std::uint64_t resent_packets = 0;
};

class Camera {
 public:
  virtual ~Camera() = default;
  virtual std::string describe() const = 0;
  virtual IoStatus start() noexcept = 0;
  virtual IoStatus stop() noexcept = 0;
  virtual IoStatus trigger_software() noexcept = 0;
  // Waits up to timeout_us for the next frame; the view stays valid until the next call.
  virtual IoStatus next_frame(FrameView& frame, int timeout_us) noexcept = 0;
  virtual CameraCounters counters() const noexcept = 0;
};

}  // namespace rig::drivers
