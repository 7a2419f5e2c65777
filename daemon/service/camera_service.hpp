#pragma once
// Pulls frames from the rig's camera on its own thread (never the RT loop), ties each to the
// loop cycle it was taken at, and streams downscaled JPEGs (at most camera_max_hz) to the
// page. Per-run frame files and the archive index come with the hardware cameras.
#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "loop_channels.hpp"
#include "rig/drivers/camera.hpp"
#include "stream_sink.hpp"

namespace rig::service {

class CameraService {
 public:
  CameraService(std::unique_ptr<drivers::Camera> camera, rt::LoopChannels& channels, int max_hz);
  ~CameraService();
  void add_sink(StreamSink* sink) { sinks_.push_back(sink); }
  void start();
  void stop();
  std::uint64_t frames_sent() const { return sent_.load(); }

 private:
  void run();
  std::unique_ptr<drivers::Camera> camera_;
  rt::LoopChannels* channels_;
  int max_hz_;
  std::vector<StreamSink*> sinks_;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> sent_{0};
};

// JPEG of an 8-bit grey image (libturbojpeg), quality 0..100.
std::vector<std::uint8_t> encode_jpeg_gray(const std::uint8_t* pixels, int width, int height, int quality);
std::string base64(const std::vector<std::uint8_t>& bytes);

}  // namespace rig::service
