#include "aravis_camera.hpp"

#include <arv.h>

#include <algorithm>
#include <stdexcept>

#include "clock/monotonic_clock.hpp"

namespace rig::drivers {
namespace {

// The one place a GError becomes text: "<what>: <message>", and the error is freed.
std::string take_error(GError* error, const std::string& what) {
  std::string text = what + ": " + (error != nullptr ? error->message : "unknown error");
  if (error != nullptr) g_error_free(error);
  return text;
}

ArvPixelFormat arv_format(PixelFormat format) {
  switch (format) {
    case PixelFormat::kRgb8:
      return ARV_PIXEL_FORMAT_RGB_8_PACKED;
    case PixelFormat::kYuyv:
      return ARV_PIXEL_FORMAT_YUV_422_YUYV_PACKED;
    case PixelFormat::kMono8:
      break;
  }
  return ARV_PIXEL_FORMAT_MONO_8;
}

}  // namespace

void GObjectUnref::operator()(void* object) const noexcept {
  if (object != nullptr) g_object_unref(object);
}

AravisCamera::AravisCamera(const std::string& id, const CameraSettings& settings) : id_(id) {
  GError* error = nullptr;
  camera_.reset(arv_camera_new(id.c_str(), &error));
  if (!camera_) throw std::runtime_error(take_error(error, "camera '" + id + "': cannot open"));
  const char* vendor = arv_camera_get_vendor_name(camera_.get(), nullptr);
  const char* model = arv_camera_get_model_name(camera_.get(), nullptr);
  description_ = std::string(vendor != nullptr ? vendor : "?") + " " +
                 (model != nullptr ? model : "?") + " (" + id + ")";
  configure(settings);
  create_stream(settings.buffer_count);
}

AravisCamera::~AravisCamera() {
  stop();
  give_back();
}

void AravisCamera::configure(const CameraSettings& s) {
  ArvCamera* cam = camera_.get();
  GError* error = nullptr;
  const auto check = [&](const std::string& setting) {
    if (error != nullptr)
      throw std::runtime_error(take_error(error, "camera '" + id_ + "': " + setting));
  };
  arv_camera_set_acquisition_mode(cam, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
  check("acquisition mode");
  arv_camera_set_pixel_format(cam, arv_format(s.pixel_format), &error);
  check("pixel format");
  arv_camera_set_region(cam, s.offset_x, s.offset_y, s.width, s.height, &error);
  check("region " + std::to_string(s.width) + "x" + std::to_string(s.height));
  arv_camera_set_exposure_time(cam, s.exposure_us, &error);
  check("exposure " + std::to_string(s.exposure_us) + " us");
  // Setting the frame rate turns triggering off on many cameras: the trigger comes after.
  arv_camera_set_frame_rate(cam, s.frame_rate_hz, &error);
  check("frame rate " + std::to_string(s.frame_rate_hz) + " Hz");
  if (s.hardware_trigger || s.software_trigger) {
    arv_camera_set_trigger(cam, s.hardware_trigger ? "Line1" : "Software", &error);
    check(s.hardware_trigger ? "trigger source Line1" : "trigger source Software");
  } else {
    arv_camera_clear_triggers(cam, &error);
    check("free-run (triggers off)");
  }
  if (arv_camera_is_gv_device(cam)) {
    arv_camera_gv_set_packet_size(cam, s.packet_size, &error);  // explicit: probing fails on some
    check("packet size " + std::to_string(s.packet_size) + " B");
  }
}

void AravisCamera::create_stream(int buffer_count) {
  GError* error = nullptr;
  stream_.reset(arv_camera_create_stream(camera_.get(), nullptr, nullptr, &error));
  if (!stream_)
    throw std::runtime_error(take_error(error, "camera '" + id_ + "': cannot create the stream"));
  const guint payload = arv_camera_get_payload(camera_.get(), &error);
  if (error != nullptr)
    throw std::runtime_error(take_error(error, "camera '" + id_ + "': payload size"));
  if (ARV_IS_GV_STREAM(stream_.get())) {
    // The receive buffer holds several frames, not one (Aravis' "auto" is one payload), so a
    // receiver thread that a busy machine does not schedule during a frame's burst of packets
    // has room for them. (The incomplete frames seen under ./rig stress came at the stream's
    // start and were not cured by this.) The kernel caps it at net.core.rmem_max [B].
    const auto buffer_B = static_cast<gint>(std::clamp<guint>(4U * payload, 1U << 20, 16U << 20));
    g_object_set(stream_.get(), "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_FIXED,
                 "socket-buffer-size", buffer_B, nullptr);
  }
  for (int i = 0; i < buffer_count; ++i)
    arv_stream_push_buffer(stream_.get(), arv_buffer_new(payload, nullptr));
}

IoStatus AravisCamera::start() noexcept {
  GError* error = nullptr;
  arv_camera_start_acquisition(camera_.get(), &error);
  if (error != nullptr) {
    g_error_free(error);
    return IoStatus::kLinkDown;
  }
  acquiring_ = true;
  return IoStatus::kOk;
}

IoStatus AravisCamera::stop() noexcept {
  if (!acquiring_) return IoStatus::kOk;
  acquiring_ = false;
  GError* error = nullptr;
  arv_camera_stop_acquisition(camera_.get(), &error);
  if (error != nullptr) {
    g_error_free(error);
    return IoStatus::kLinkDown;
  }
  return IoStatus::kOk;
}

IoStatus AravisCamera::trigger_software() noexcept {
  GError* error = nullptr;
  arv_camera_software_trigger(camera_.get(), &error);
  if (error != nullptr) {
    g_error_free(error);
    return IoStatus::kLinkDown;
  }
  return IoStatus::kOk;
}

void AravisCamera::give_back() noexcept {
  if (lent_ != nullptr && stream_) arv_stream_push_buffer(stream_.get(), lent_);
  lent_ = nullptr;
}

IoStatus AravisCamera::next_frame(FrameView& frame, int timeout_us) noexcept {
  give_back();
  ArvBuffer* buffer =
      arv_stream_timeout_pop_buffer(stream_.get(), static_cast<guint64>(timeout_us));
  if (buffer == nullptr) {
    ++timeouts_;
    return IoStatus::kTimeout;
  }
  const auto arrived_ns = static_cast<std::uint64_t>(MonotonicClock().now_ns());
  if (arv_buffer_get_status(buffer) != ARV_BUFFER_STATUS_SUCCESS) {
    ++incomplete_;  // missing packets, aborted, ...: the buffer goes straight back
    arv_stream_push_buffer(stream_.get(), buffer);
    return IoStatus::kBadData;
  }
  size_t size = 0;
  const void* data = arv_buffer_get_data(buffer, &size);
  lent_ = buffer;
  ++frames_;
  frame.pixels = {static_cast<const std::uint8_t*>(data), size};
  frame.width = arv_buffer_get_image_width(buffer);
  frame.height = arv_buffer_get_image_height(buffer);
  frame.format = PixelFormat::kMono8;
  frame.camera_timestamp_ns = arv_buffer_get_timestamp(buffer);
  frame.host_timestamp_ns = arrived_ns;
  frame.frame_id = arv_buffer_get_frame_id(buffer);
  return IoStatus::kOk;
}

CameraCounters AravisCamera::counters() const noexcept {
  CameraCounters c;
  c.frames = frames_;
  guint64 completed = 0, failures = 0, underruns = 0;
  arv_stream_get_statistics(stream_.get(), &completed, &failures, &underruns);
  c.dropped = failures + underruns;
  if (ARV_IS_GV_STREAM(stream_.get())) {
    guint64 resent = 0, missing = 0;
    arv_gv_stream_get_statistics(ARV_GV_STREAM(stream_.get()), &resent, &missing);
    c.resent_packets = resent;
    c.missing_packets = missing;
  }
  return c;
}

}  // namespace rig::drivers
