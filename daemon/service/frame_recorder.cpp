#include "frame_recorder.hpp"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "clock/monotonic_clock.hpp"

namespace rig::service {
namespace {
std::int64_t row_time_ns(const drivers::FrameView& frame) {
  return static_cast<std::int64_t>(frame.host_timestamp_ns);
}
}  // namespace

FrameRecorder::FrameRecorder(IndexSink index_sink, std::string frames_dir, double loop_rate_hz)
    : index_sink_(std::move(index_sink)),
      frames_dir_(std::move(frames_dir)),
      period_ns_(static_cast<std::int64_t>(std::llround(1e9 / loop_rate_hz))) {
  std::filesystem::create_directories(frames_dir_);
}

void FrameRecorder::open_run(std::int64_t run_id) {
  finish_run();
  run_id_ = run_id;
  frame_no_ = 0;
  failed_ = false;
  try {
    file_ = std::make_unique<archive::FrameFile>(frames_dir_ + "/run-" + std::to_string(run_id) +
                                                 ".frames");
  } catch (const std::exception& e) {
    failed_ = true;
    spdlog::error("camera: run {}: frames not recorded: {}", run_id, e.what());
  }
}

void FrameRecorder::write_index() {
  if (pending_.empty()) return;
  index_sink_(std::move(pending_));
  pending_.clear();
}

void FrameRecorder::finish_run() {
  if (!file_) return;
  try {
    file_->flush();  // pixels on the disk before their index rows
    write_index();
  } catch (const std::exception& e) {
    spdlog::error("camera: run {}: {}", run_id_, e.what());
  }
  file_.reset();
}

// The loop cycle the frame was exposed at. Cameras stamping on CLOCK_MONOTONIC (V4L2, the
// simulated one) are on the loop's time line already; others (GigE tick) are mapped with
// the smallest arrival - camera time seen so far. The loop's snapshot says which cycle ran
// at which loop time; its host time is estimated by the smallest (now - loop time) seen.
std::int64_t FrameRecorder::sample_of(const drivers::FrameView& frame,
                                      const rt::StatusSnapshot& status) {
  const auto arrival = static_cast<std::int64_t>(frame.host_timestamp_ns);
  auto exposure = static_cast<std::int64_t>(frame.camera_timestamp_ns);
  constexpr std::int64_t kSameClock_ns = 1'000'000'000;
  if (exposure == 0) {
    exposure = arrival;
  } else if (std::llabs(arrival - exposure) > kSameClock_ns) {
    const std::int64_t offset = arrival - exposure;
    camera_to_host_ns_ = camera_to_host_ns_ ? std::min(*camera_to_host_ns_, offset) : offset;
    exposure += *camera_to_host_ns_;
  }
  const auto loop_time_ns = static_cast<std::int64_t>(std::llround(status.t_s * 1e9));
  const std::int64_t start = drivers::MonotonicClock{}.now_ns() - loop_time_ns;
  loop_start_ns_ = loop_start_ns_ ? std::min(*loop_start_ns_, start) : start;
  const std::int64_t snapshot_host_ns = *loop_start_ns_ + loop_time_ns;
  const std::int64_t cycles_back = (snapshot_host_ns - exposure) / period_ns_;
  return std::max<std::int64_t>(0, static_cast<std::int64_t>(status.cycle) - cycles_back);
}

void FrameRecorder::record(const drivers::FrameView& frame, const rt::StatusSnapshot& status) {
  if (status.run_id == 0) {
    finish_run();
    run_id_ = 0;
    return;
  }
  if (status.run_id != run_id_) open_run(status.run_id);
  if (failed_ || !file_) {
    ++lost_;
    return;
  }
  try {
    archive::FrameRow row;
    row.run_id = run_id_;
    row.frame_no = frame_no_;
    row.sample_index = sample_of(frame, status);
    row.camera_ts_ns = static_cast<std::int64_t>(frame.camera_timestamp_ns);
    row.host_ts_ns = static_cast<std::int64_t>(frame.host_timestamp_ns);
    row.file_offset = file_->append(frame.pixels);
    row.bytes = static_cast<std::int64_t>(frame.pixels.size());
    row.width = frame.width;
    row.height = frame.height;
    row.file = file_->path();
    pending_.push_back(std::move(row));
    ++frame_no_;
    ++written_;
    constexpr std::int64_t kIndexEvery_ns = 200'000'000;  // hand rows over 5x per second
    if (row_time_ns(frame) - last_index_write_ns_ >= kIndexEvery_ns) {
      file_->flush();
      write_index();
      last_index_write_ns_ = row_time_ns(frame);
    }
  } catch (const std::exception& e) {
    failed_ = true;  // disk full or archive locked: stop for this run, keep the loop untouched
    ++lost_;
    spdlog::error("camera: run {}: frame recording stopped: {}", run_id_, e.what());
  }
}

}  // namespace rig::service
