#pragma once
// Pulls frames from the rig's camera on its own thread (never the RT loop), ties each to the
// loop cycle it was taken at, records every frame of a run (FrameRecorder: per-run frame
// file + archive index) and streams downscaled JPEGs (at most camera_max_hz) to the page.
#include <atomic>
#include <chrono>
#include <memory>
#include <thread>
#include <vector>

#include "frame_recorder.hpp"
#include "loop_channels.hpp"
#include "rig/drivers/camera.hpp"
#include "stream_sink.hpp"

namespace rig::service {

class CameraService {
 public:
  // recorder may be null (frames only streamed, not archived).
  CameraService(std::unique_ptr<drivers::Camera> camera, rt::LoopChannels& channels, int max_hz,
                std::unique_ptr<FrameRecorder> recorder = nullptr, int lost_after_ms = 1000);
  ~CameraService();
  void add_sink(StreamSink* sink) { sinks_.push_back(sink); }
  void start();
  void stop();
  std::uint64_t frames_sent() const { return sent_.load(); }

 private:
  void run();
  void stream(const drivers::FrameView& frame, const rt::StatusSnapshot& st);
  void watch_for_loss(bool frame_arrived, const rt::StatusSnapshot& st);
  std::unique_ptr<drivers::Camera> camera_;
  std::unique_ptr<FrameRecorder> recorder_;
  rt::LoopChannels* channels_;
  int max_hz_;
  int lost_after_ms_;  // no frame for this long while recording = camera lost (0 = never)
  std::chrono::steady_clock::time_point last_frame_{};
  std::vector<StreamSink*> sinks_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> sent_{0};
};

// JPEG of an 8-bit grey image (libturbojpeg), quality 0..100.
std::vector<std::uint8_t> encode_jpeg_gray(const std::uint8_t* pixels, int width, int height,
                                           int quality);
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace rig::service
