#include "camera_service.hpp"

#include <spdlog/spdlog.h>
#include <turbojpeg.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <memory>

#include "rig/proto/messages.hpp"

namespace rig::service {
namespace {

struct TjDeleter {
  void operator()(void* handle) const noexcept { tjDestroy(handle); }
};

}  // namespace

std::vector<std::uint8_t> encode_jpeg_gray(const std::uint8_t* pixels, int width, int height,
                                           int quality) {
  const std::unique_ptr<void, TjDeleter> handle(tjInitCompress());
  unsigned char* jpeg = nullptr;
  unsigned long size = 0;
  if (!handle || tjCompress2(handle.get(), pixels, width, width, height, TJPF_GRAY, &jpeg, &size,
                             TJSAMP_GRAY, quality, TJFLAG_FASTDCT) != 0) {
    if (jpeg != nullptr) tjFree(jpeg);
    return {};
  }
  std::vector<std::uint8_t> out(jpeg, jpeg + size);
  tjFree(jpeg);
  return out;
}

std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t n =
        (static_cast<std::uint32_t>(bytes[i]) << 16U) |
        (i + 1 < bytes.size() ? static_cast<std::uint32_t>(bytes[i + 1]) << 8U : 0U) |
        (i + 2 < bytes.size() ? bytes[i + 2] : 0U);
    out += kAlphabet[(n >> 18U) & 63U];
    out += kAlphabet[(n >> 12U) & 63U];
    out += i + 1 < bytes.size() ? kAlphabet[(n >> 6U) & 63U] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[n & 63U] : '=';
  }
  return out;
}

CameraService::CameraService(std::unique_ptr<drivers::Camera> camera, rt::LoopChannels& channels,
                             int max_hz, std::unique_ptr<FrameRecorder> recorder, int lost_after_ms)
    : camera_(std::move(camera)),
      recorder_(std::move(recorder)),
      channels_(&channels),
      max_hz_(max_hz),
      lost_after_ms_(lost_after_ms) {}

CameraService::~CameraService() {
  stop();
}

void CameraService::start() {
  if (camera_->start() != drivers::IoStatus::kOk)
    spdlog::warn("camera: {} did not start", camera_->describe());
  thread_ = std::thread([this] { run(); });
}

void CameraService::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true);
  thread_.join();
  camera_->stop();
  if (recorder_) recorder_->finish_run();
}

void CameraService::run() {
  const auto min_interval = std::chrono::microseconds(1'000'000 / std::max(max_hz_, 1));
  auto last_sent = std::chrono::steady_clock::now() - min_interval;
  while (!stop_.load()) {
    drivers::FrameView frame;
    const bool arrived = camera_->next_frame(frame, 100'000) == drivers::IoStatus::kOk;
    const rt::StatusSnapshot st = channels_->status.read();
    watch_for_loss(arrived, st);
    if (!arrived) continue;
    if (recorder_) recorder_->record(frame, st);  // every frame of a run, not just the page's share
    const auto now = std::chrono::steady_clock::now();
    if (now - last_sent < min_interval || frame.format != drivers::PixelFormat::kMono8) continue;
    last_sent = now;
    stream(frame, st);
  }
}

// A run is filmed or it is not a valid run: no frame for lost_after_ms while recording
// faults it (the loop stops the motor); frames flowing again clear the condition.
void CameraService::watch_for_loss(bool frame_arrived, const rt::StatusSnapshot& st) {
  const auto now = std::chrono::steady_clock::now();
  if (frame_arrived || st.run_id == 0 || lost_after_ms_ <= 0) {
    last_frame_ = now;  // not recording: a run starting now gets the full grace period
    if (frame_arrived) {
      rt::FaultCode lost = rt::FaultCode::kCameraLost;
      channels_->service_fault.compare_exchange_strong(lost, rt::FaultCode::kNone);
    }
    return;
  }
  if (now - last_frame_ < std::chrono::milliseconds(lost_after_ms_)) return;
  rt::FaultCode none = rt::FaultCode::kNone;
  if (channels_->service_fault.compare_exchange_strong(none, rt::FaultCode::kCameraLost))
    spdlog::critical("camera: {} sent no frame for {} ms during run {}: faulting the run",
                     camera_->describe(), lost_after_ms_, st.run_id);
}

void CameraService::stream(const drivers::FrameView& frame, const rt::StatusSnapshot& st) {
  proto::CameraFrame message;
  message.type = "frame";
  message.run_id = st.run_id;
  message.t_s = st.t_s;
  message.sample_cycle = static_cast<std::int64_t>(st.cycle);
  message.width = frame.width;
  message.height = frame.height;
  message.jpeg_base64 =
      base64(encode_jpeg_gray(frame.pixels.data(), frame.width, frame.height, 70));
  auto json = std::make_shared<const std::string>(nlohmann::json(message).dump());
  for (StreamSink* sink : sinks_) sink->publish(json);
  sent_.fetch_add(1);
}

}  // namespace rig::service
