#pragma once
// Haptic playback inside rigd: one session at a time on its own thread (the servo itself
// runs on the device's RT thread). The mass-spring cornea goes to the page as MeshFrame
// messages (~50 Hz); a live session is fed the loop's force and blade depth at 1 kHz.
#include <atomic>
#include <memory>
#include <mutex>
#include <thread>

#include "haptic_control.hpp"
#include "loop_channels.hpp"
#include "rig/config/rigd_config.hpp"
#include "stream_sink.hpp"

namespace rig::haptic {
class Playback;
struct MeshSnapshot;
}  // namespace rig::haptic

namespace rig::service {

class HapticService final : public api::HapticControl {
 public:
  HapticService(const config::RigdConfig& config, rt::LoopChannels& channels, StreamSink& sink);
  ~HapticService() override;
  bool start(const proto::HapticRequest& request) override;
  bool stop() override;
  proto::HapticStatus status() override;

 private:
  std::unique_ptr<haptic::Playback> set_up(const proto::HapticRequest& request);
  void run(std::shared_ptr<haptic::Playback> playback);
  void feed_live(haptic::Playback& playback, const std::atomic<bool>& done);
  void publish_mesh(const haptic::MeshSnapshot& mesh);
  void join();

  const config::RigdConfig& config_;
  rt::LoopChannels& channels_;
  StreamSink& sink_;
  std::mutex mutex_;
  proto::HapticStatus status_;
  std::atomic<bool> cancel_{false};
  std::atomic<bool> running_{false};
  std::thread worker_;
};

}  // namespace rig::service
