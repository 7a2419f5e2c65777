#pragma once
// Writes the camera's frames of each run to the run's frame file (<frames_dir>/run-<id>.frames)
// and indexes every frame in the archive (table `frames`), tied to the loop cycle (= sample
// index) of its exposure. Runs on the camera thread, never the RT loop. A write error (disk
// full) stops frame recording for that run with one error in the log; the run itself, whose
// samples the recorder writes, is not affected.
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "archive.hpp"
#include "frame_file.hpp"
#include "rig/drivers/camera.hpp"
#include "status_snapshot.hpp"

namespace rig::service {

class FrameRecorder {
 public:
  using IndexSink = std::function<void(std::vector<archive::FrameRow>)>;
  // index_sink receives the index rows of frames already flushed to their file (the
  // recorder's archive transaction in rigd).
  FrameRecorder(IndexSink index_sink, std::string frames_dir, double loop_rate_hz);
  // status: the loop's latest snapshot, read when the frame arrived.
  void record(const drivers::FrameView& frame, const rt::StatusSnapshot& status);
  void finish_run();  // flushes the frame file to the disk
  std::uint64_t frames_written() const { return written_; }
  std::uint64_t frames_lost() const { return lost_; }

 private:
  std::int64_t sample_of(const drivers::FrameView& frame, const rt::StatusSnapshot& status);
  void open_run(std::int64_t run_id);
  void write_index();  // pending rows to the index sink

  IndexSink index_sink_;
  std::string frames_dir_;
  std::int64_t period_ns_;
  std::unique_ptr<archive::FrameFile> file_;
  std::int64_t run_id_ = 0;
  std::int64_t frame_no_ = 0;
  bool failed_ = false;  // this run's frame file could not be written
  std::optional<std::int64_t> camera_to_host_ns_;
  std::optional<std::int64_t> loop_start_ns_;  // CLOCK_MONOTONIC of the loop's t = 0 (estimate)
  std::vector<archive::FrameRow> pending_;     // index rows not yet in the archive
  std::int64_t last_index_write_ns_ = 0;
  std::uint64_t written_ = 0, lost_ = 0;
};

}  // namespace rig::service
