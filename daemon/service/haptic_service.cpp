#include "haptic_service.hpp"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdlib>

#include "archive.hpp"
#include "playback.hpp"
#include "virtual_hand.hpp"

namespace rig::service {

HapticService::HapticService(const config::RigdConfig& config, rt::LoopChannels& channels,
                             StreamSink& sink)
    : config_(config), channels_(channels), sink_(sink) {
  status_.state = "idle";
}

HapticService::~HapticService() {
  cancel_.store(true);
  join();
}

void HapticService::join() {
  if (worker_.joinable()) worker_.join();
}

std::unique_ptr<haptic::Playback> HapticService::set_up(const proto::HapticRequest& request) {
  haptic::PlaybackOptions o;
  o.device = request.device;
  o.source = haptic::SourceSpec::parse(request.source);
  o.velocity_mm_s = request.velocity_mm_s.value_or(2.0);
  o.iop_mmHg = request.iop_mmHg.value_or(15.0);
  o.depth_mm = request.depth_mm;
  o.mesh_n = static_cast<int>(request.mesh_n.value_or(13));
  o.max_s = request.max_s.value_or(120.0);
  if (const char* library = std::getenv("RIG_LIBHD")) o.library = library;
  const bool own_model =
      o.source.kind == haptic::SourceSpec::Kind::kModel && !o.source.argument.empty();
  const model::ForceModel reference =
      model::ForceModel::load(own_model ? o.source.argument : config_.model.file);
  std::optional<model::RunData> run;
  if (o.source.kind == haptic::SourceSpec::Kind::kRun) {
    std::size_t used = 0;
    const long long id = std::stoll(o.source.argument, &used);
    if (used != o.source.argument.size())
      throw std::invalid_argument("source run:ID: '" + o.source.argument + "' is not a run id");
    archive::Archive archive(config_.archive.path, true);
    run = archive.load_run(id);
  }
  return std::make_unique<haptic::Playback>(o, reference, std::move(run));
}

bool HapticService::start(const proto::HapticRequest& request) {
  if (running_.exchange(true)) return false;  // claimed: a second request gets 409
  join();
  std::shared_ptr<haptic::Playback> playback;
  try {
    playback = set_up(request);
  } catch (const std::exception& e) {
    running_.store(false);
    std::lock_guard lock(mutex_);
    status_ = proto::HapticStatus{};
    status_.state = "failed";
    status_.error = e.what();
    throw;
  }
  {
    std::lock_guard lock(mutex_);
    status_ = proto::HapticStatus{};
    status_.state = "running";
    status_.device = playback->device_name();
    status_.source = request.source;
  }
  cancel_.store(false);
  worker_ = std::thread([this, playback] { run(playback); });
  spdlog::info("haptic: {} playing {}", playback->device_name(), request.source);
  return true;
}

bool HapticService::stop() {
  if (!running_.load()) return false;
  cancel_.store(true);
  return true;
}

proto::HapticStatus HapticService::status() {
  std::lock_guard lock(mutex_);
  return status_;
}

void HapticService::feed_live(haptic::Playback& playback, const std::atomic<bool>& done) {
  const double surface = config_.loop.motion.surface_mm;
  while (!done.load()) {
    const rt::StatusSnapshot st = channels_.status.read();
    playback.live_source()->update(st.force_N);
    if (playback.following_hand() != nullptr)
      playback.following_hand()->set_depth(st.position_mm - surface);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
}

void HapticService::publish_mesh(const haptic::MeshSnapshot& mesh) {
  proto::MeshFrame frame;
  frame.type = "mesh";
  frame.t_s = mesh.t_s;
  frame.tip_depth_mm = mesh.tip_depth_mm;
  frame.force_N = mesh.force_N;
  frame.punctured = mesh.punctured;
  frame.x_mm.assign(mesh.x_mm, mesh.x_mm + mesh.point_count);
  frame.z_mm.assign(mesh.z_mm, mesh.z_mm + mesh.point_count);
  if (mesh.grid_count > 0) {  // the whole mesh, for the page's 3D view
    frame.grid_x_mm.emplace(mesh.grid_x_mm, mesh.grid_x_mm + mesh.grid_count);
    frame.grid_y_mm.emplace(mesh.grid_y_mm, mesh.grid_y_mm + mesh.grid_count);
    frame.grid_z_mm.emplace(mesh.grid_z_mm, mesh.grid_z_mm + mesh.grid_count);
  }
  sink_.publish(std::make_shared<const std::string>(nlohmann::json(frame).dump()));
}

void HapticService::run(std::shared_ptr<haptic::Playback> playback) {
  std::atomic<bool> done{false};
  std::thread feeder;
  if (playback->live_source() != nullptr) feeder = std::thread([&] { feed_live(*playback, done); });
  haptic::PlaybackResult result;
  std::string error;
  try {
    result =
        playback->run([this](const haptic::MeshSnapshot& mesh) { publish_mesh(mesh); }, &cancel_);
  } catch (const std::exception& e) {
    error = e.what();
  }
  done.store(true);
  if (feeder.joinable()) feeder.join();
  {
    std::lock_guard lock(mutex_);
    const haptic::SessionReport& r = result.report;
    if (!r.fault.empty()) error = r.fault;
    status_.state = error.empty() ? "done" : "failed";
    if (!error.empty()) status_.error = error;
    status_.rate_hz = r.rate_hz;
    status_.ticks = static_cast<std::int64_t>(r.ticks);
    status_.overruns = static_cast<std::int64_t>(r.overruns + r.late_ticks);
    status_.tick_p99_us = r.tick_p99_us;
    if (result.vs_model)
      status_.rmse_vs_model_N = result.vs_model->rmse_N,
      status_.max_vs_model_N = result.vs_model->max_N;
    if (result.vs_run)
      status_.rmse_vs_run_N = result.vs_run->rmse_N, status_.max_vs_run_N = result.vs_run->max_N;
    status_.mesh_vertices = r.mesh_vertices;
    status_.mesh_springs = r.mesh_springs;
    status_.watchdog_tripped = r.watchdog_tripped;
    status_.longest_tick_gap_ms = r.longest_tick_gap_ms;
  }
  spdlog::info("haptic: session {} ({} ticks at {:.1f} Hz)",
               error.empty() ? "done" : "failed: " + error, result.report.ticks,
               result.report.rate_hz);
  running_.store(false);
}

}  // namespace rig::service
