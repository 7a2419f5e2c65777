#pragma once
// A haptic playback put together from what the user asked for (CLI or API): the force
// source, the device (simulated Phantom with a virtual hand, or a Phantom through
// OpenHaptics), the session, and, for a simulated hand, the fidelity figures afterwards.
// Everything that can fail is done in the constructor, with a message naming the option.
#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "felt_error.hpp"
#include "force_model.hpp"
#include "haptic_session.hpp"
#include "live_force_source.hpp"
#include "run_data.hpp"
#include "source_spec.hpp"

namespace rig::drivers {
class FollowingHand;
class SimPhantom;
class VirtualHand;
}  // namespace rig::drivers

namespace rig::haptic {

struct PlaybackOptions {
  std::string device = "sim";  // sim or phantom
  SourceSpec source;
  double velocity_mm_s = 2.0;        // virtual hand [mm/s]
  double iop_mmHg = 15.0;            // the model's IOP [mmHg]
  std::optional<double> depth_mm;    // virtual hand's deepest point [mm]
  int mesh_n = 13;                   // 13: the paper's 169 vertices, 886 springs
  bool real_time = true;             // sim: 1 kHz on a real-time thread; false: virtual clock
  std::string library = "libHD.so";  // OpenHaptics HD library
  double max_s = 120.0;              // session limit [s]
};

struct PlaybackResult {
  SessionReport report;
  std::optional<ErrorFigures> vs_model;  // simulated hand only
  std::optional<ErrorFigures> vs_run;    // simulated hand and a run to compare with
};

class Playback {
 public:
  // reference: the model the felt force is compared with (and rendered, for a model source).
  // run: the recorded run (rendered for a run source, else only compared with), if any.
  Playback(const PlaybackOptions& options, const model::ForceModel& reference,
           std::optional<model::RunData> run);
  ~Playback();
  PlaybackResult run(const std::function<void(const MeshSnapshot&)>& on_mesh,
                     const std::atomic<bool>* cancel);
  LiveForceSource* live_source() { return live_; }
  drivers::FollowingHand* following_hand() { return following_; }
  const std::string& device_name() const { return device_name_; }

 private:
  PlaybackOptions options_;
  std::unique_ptr<ForceSource> reference_;
  std::unique_ptr<ForceSource> run_reference_;
  std::unique_ptr<ForceSource> source_;
  LiveForceSource* live_ = nullptr;
  std::unique_ptr<drivers::VirtualHand> hand_;
  drivers::FollowingHand* following_ = nullptr;
  std::unique_ptr<drivers::HapticDevice> device_;
  drivers::SimPhantom* sim_ = nullptr;
  std::unique_ptr<HapticSession> session_;
  std::string device_name_;
};

}  // namespace rig::haptic
