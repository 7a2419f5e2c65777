#pragma once
// GigE Vision / USB3 Vision camera through Aravis 0.8. Everything is set explicitly at setup
// (pixel format, ROI, exposure, frame rate, trigger, packet size, socket buffer, buffer
// pool) because auto-probing fails on some devices and on Aravis's simulator; setup throws
// with the camera's id and the failing setting named. Cyclic calls return IoStatus. Every
// GObject lives in a unique_ptr with g_object_unref; GError becomes text in one place.
#include <atomic>
#include <memory>
#include <string>

#include "rig/drivers/camera.hpp"

// The C library's own struct tags, declared here so the header need not include it.
// NOLINTBEGIN(bugprone-reserved-identifier)
struct _ArvCamera;
struct _ArvStream;
struct _ArvBuffer;
// NOLINTEND(bugprone-reserved-identifier)

namespace rig::drivers {

struct GObjectUnref {
  void operator()(void* object) const noexcept;
};

class AravisCamera final : public Camera {
 public:
  // id: an Aravis device id ("Aravis-GV01"), or an IP address ("127.0.0.1"). Throws.
  AravisCamera(const std::string& id, const CameraSettings& settings);
  ~AravisCamera() override;
  AravisCamera(const AravisCamera&) = delete;
  AravisCamera& operator=(const AravisCamera&) = delete;

  std::string describe() const override { return description_; }
  IoStatus start() noexcept override;
  IoStatus stop() noexcept override;
  IoStatus trigger_software() noexcept override;
  IoStatus next_frame(FrameView& frame, int timeout_us) noexcept override;
  CameraCounters counters() const noexcept override;

 private:
  void configure(const CameraSettings& s);
  void create_stream(int buffer_count);
  void give_back() noexcept;  // returns the frame handed out last to the pool

  std::string id_, description_;
  std::unique_ptr<_ArvCamera, GObjectUnref> camera_;
  std::unique_ptr<_ArvStream, GObjectUnref> stream_;
  _ArvBuffer* lent_ = nullptr;  // the buffer behind the last FrameView (owned by the stream)
  bool acquiring_ = false;
  std::uint64_t frames_ = 0, incomplete_ = 0, timeouts_ = 0;
};

}  // namespace rig::drivers
