#pragma once
// The run archive: one SQLite file in WAL mode. Runs (metadata), their samples, events and
// extra channels. The recorder commits every flush interval, so a crash of rigd loses at
// most the last uncommitted batch; runs left "recording" are marked "interrupted" at the
// next start and keep everything committed.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "run_data.hpp"
#include "run_types.hpp"
#include "sqlite_handle.hpp"

namespace rig::archive {

struct NewRun {
  std::string eye_id;
  double iop_mmHg = 15.0;
  double velocity_mm_s = 2.0;
  double depth_mm = 14.0;
  double hold_s = 0.0;
  std::optional<double> post_mortem_h;
  std::string operator_name;
  std::string notes;
  std::vector<std::pair<std::string, std::string>> meta;
  std::string config_hash;
  std::string software_version;
  double surface_mm = 0.0;  // carriage position of first contact
  double rate_hz = 1000.0;
};

struct RunRow {
  std::int64_t id = 0;
  std::string eye_id;
  std::optional<double> iop_mmHg;
  std::optional<double> velocity_mm_s;
  std::optional<double> depth_mm;
  std::string started_at;
  std::string ended_at;
  std::string
      outcome;  // armed, recording, completed, stopped, fault, cancelled, interrupted, imported
  std::string reason;
  std::string source;
  std::int64_t samples = 0;
};

struct EventRow {
  double t_s = 0.0;
  std::string kind;
  std::string message;
};

// One camera frame of a run: where it is in the run's frame file and which sample (loop
// cycle) its exposure was triggered at.
struct FrameRow {
  std::int64_t run_id = 0;
  std::int64_t frame_no = 0;       // 0, 1, ... in the run
  std::int64_t sample_index = -1;  // loop cycle of the trigger (-1: free-running, not tied)
  std::int64_t camera_ts_ns = 0;   // camera's clock
  std::int64_t host_ts_ns = 0;     // CLOCK_MONOTONIC at arrival
  std::int64_t file_offset = 0;    // [B] into the frame file
  std::int64_t bytes = 0;
  int width = 0, height = 0;
  std::string file;  // the run's frame file
};

class Archive {
 public:
  explicit Archive(const std::string& path, bool read_only = false);

  std::int64_t create_run(const NewRun& run);
  void mark_started(std::int64_t run_id);
  void finish_run(std::int64_t run_id, const std::string& outcome, const std::string& reason);
  // A run the loop refused to arm: its row (still 'armed', no sample) and metadata go.
  void discard_unstarted_run(std::int64_t run_id);
  int recover_interrupted();
  // Runs left 'importing' by a `rig import` that no longer runs (killed, crashed, power cut):
  // their rows go (the file they came from still holds every sample) and their sources are
  // returned so the caller can say which files to import again. An import whose process still
  // runs is left alone (import_process.hpp).
  std::vector<std::string> remove_abandoned_imports();

  // For rigd's writers: SQLite would otherwise copy its log into the database inside whichever
  // commit takes the log past 1000 pages (~4 MB: every ~40 s of samples, and the first commit
  // after a power cut), a commit of hundreds of ms in the middle of a cut, and a power cut
  // then takes more than one flush interval. The recorder checkpoints between runs instead.
  void defer_checkpoints();
  // Commits are written to the log but not synced (synchronous=NORMAL): the caller syncs
  // `<path>-wal` after each commit itself (the recorder's WalSyncer), so a slow sync never
  // holds up the next write. Until it has, a power cut can roll the commit back.
  void defer_log_syncs();
  // Copies the log into the database as far as readers allow: the frames left [pages].
  int checkpoint() { return db_.checkpoint_log(); }

  void begin();
  void commit();
  void rollback() noexcept;  // after a failed write: drop the open transaction, if any
  void append_sample(const rt::Sample& sample);
  void add_event(std::int64_t run_id, double t_s, const std::string& kind,
                 const std::string& message);

  std::vector<RunRow> list_runs();
  std::optional<RunRow> find_run(std::int64_t run_id);
  std::vector<std::pair<std::string, std::string>> run_meta(std::int64_t run_id);
  std::vector<EventRow> run_events(std::int64_t run_id);
  // The run as run-CSV data: t from its first sample, x from first contact.
  model::RunData load_run(std::int64_t run_id);
  void add_frame(const FrameRow& frame);  // archive_frames.cpp
  std::vector<FrameRow> run_frames(std::int64_t run_id);
  std::int64_t import_run(const model::RunData& run);
  const std::string& path() const { return db_.path(); }

 private:
  void create_schema();
  std::int64_t import_run_row(const model::RunData& run);  // archive_runs.cpp
  void import_samples(std::int64_t id, const model::RunData& run);
  void remove_run_rows(std::int64_t id) noexcept;
  RunRow read_row(Statement& q);

  Database db_;
  std::optional<Statement> insert_sample_;
  bool in_transaction_ = false;
};

std::string utc_now_iso8601();

}  // namespace rig::archive
