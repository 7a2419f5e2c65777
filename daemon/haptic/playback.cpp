#include "playback.hpp"

#include <algorithm>
#include <stdexcept>

#include "haptic/openhaptics_device.hpp"
#include "model_force_source.hpp"
#include "recorded_run_source.hpp"
#include "sim_phantom.hpp"
#include "virtual_hand.hpp"

namespace rig::haptic {

namespace {

double deepest_mm(const model::RunData& run) {
  return run.x_mm.empty() ? 0.0 : *std::max_element(run.x_mm.begin(), run.x_mm.end());
}

}  // namespace

Playback::Playback(const PlaybackOptions& options, const model::ForceModel& reference,
                   std::optional<model::RunData> run)
    : options_(options),
      reference_(std::make_unique<ModelForceSource>(reference, options.iop_mmHg)) {
  if (options.velocity_mm_s <= 0.0)
    throw std::invalid_argument("--velocity must be positive [mm/s]");
  if (run) run_reference_ = std::make_unique<RecordedRunSource>(*run);
  double depth = options.depth_mm.value_or(reference.final_depth_mm(options.iop_mmHg) + 0.5);
  switch (options.source.kind) {
    case SourceSpec::Kind::kModel:
      source_ = std::make_unique<ModelForceSource>(reference, options.iop_mmHg);
      break;
    case SourceSpec::Kind::kRun:
      if (!run) throw std::invalid_argument("haptic source run: no run was loaded");
      source_ = std::make_unique<RecordedRunSource>(*run);
      if (!options.depth_mm) depth = deepest_mm(*run);
      break;
    case SourceSpec::Kind::kLive: {
      auto live = std::make_unique<LiveForceSource>();
      live_ = live.get();
      source_ = std::move(live);
      break;
    }
  }
  if (options.device == "sim") {
    if (live_ != nullptr) {
      auto hand = std::make_unique<drivers::FollowingHand>(options.max_s);
      following_ = hand.get();
      hand_ = std::move(hand);
    } else {
      hand_ = std::make_unique<drivers::PushingHand>(options.velocity_mm_s, depth);
    }
    drivers::SimPhantomSettings settings;
    settings.real_time = options.real_time;
    auto sim = std::make_unique<drivers::SimPhantom>(settings, *hand_);
    sim_ = sim.get();
    device_ = std::move(sim);
  } else if (options.device == "phantom") {
    device_ = std::make_unique<drivers::OpenHapticsDevice>(options.library);
  } else {
    throw std::invalid_argument("--device '" + options.device + "': expected sim or phantom");
  }
  device_name_ = device_->describe();
  ServoSettings servo;
  servo.mesh.n = options.mesh_n;
  if (sim_ != nullptr) servo.surface_mm = drivers::Vec3{0.0, 0.0, 0.0};  // the virtual hand's frame
  // The session arms its 20 ms stall watchdog only on a device paced by the wall clock.
  session_ = std::make_unique<HapticSession>(*device_, *source_, servo);
}

Playback::~Playback() = default;

PlaybackResult Playback::run(const std::function<void(const MeshSnapshot&)>& on_mesh,
                             const std::atomic<bool>* cancel) {
  PlaybackResult result;
  result.report = session_->run(on_mesh, cancel, options_.max_s);
  if (sim_ != nullptr) {
    result.vs_model = felt_error(sim_->felt(), *reference_);
    if (run_reference_) result.vs_run = felt_error(sim_->felt(), *run_reference_);
  }
  return result;
}

}  // namespace rig::haptic
