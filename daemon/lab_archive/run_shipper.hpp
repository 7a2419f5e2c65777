#pragma once
// Ships one rig's local SQLite archive to the lab archive, run by run: metadata upserted,
// then samples, events and frames past the server's watermark for that run, all in one
// transaction with the new watermark. The watermark lives on the server (runs.last_idx,
// runs.events, runs.frames), so a retry after a lost commit, a rigd restart or a server
// restart re-reads it and never sends a row twice. Each transaction reads the watermark
// under the run row's lock (the metadata upsert), so two shippers of one rig cannot
// interleave; the primary keys (run uuid + sample index) refuse a duplicate besides.
// Samples go by binary COPY, sent in pieces while later rows are still read from SQLite;
// events, frames and channels by text COPY.
#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "pg_connection.hpp"
#include "sqlite_handle.hpp"

namespace rig::lab_archive {

struct Backlog {
  std::int64_t runs = 0;     // runs not yet complete on the server
  std::int64_t samples = 0;  // local samples the server does not have yet
  bool known = false;        // false until the server's watermarks were read once
};

class RunShipper {
 public:
  RunShipper(std::string sqlite_path, std::string rig_id, std::string software_version);
  // One pass over the local runs; ships at most max_samples samples. Returns the samples
  // shipped. Throws LabArchiveError (server) or ArchiveError (local file).
  std::int64_t ship_pass(PgConnection& db, std::int64_t max_samples);
  // Recomputes the backlog from the local archive and the last known server watermarks.
  Backlog backlog();
  // After a reconnect: server watermarks are read again before the next pass.
  void forget_server_state();

 private:
  struct Watermark {
    std::int64_t last_idx = -1;
    std::int64_t events = 0;
    std::int64_t frames = 0;
    std::string outcome;
    bool new_on_server = false;      // the upsert inserted the run (its channels go along)
    std::int64_t created_at_us = 0;  // the run's created_at on the server [us since 2000-01-01 UTC]
  };
  struct LocalRun {
    std::int64_t id = 0;
    std::string created_at;
    std::string outcome;
    std::string source;
    std::string uuid;
  };

  void load_server_state(PgConnection& db);
  void prepare_session(PgConnection& db);
  std::vector<LocalRun> local_runs();
  std::int64_t ship_run(PgConnection& db, const LocalRun& run, std::int64_t max_samples);
  Watermark upsert_run(PgConnection& db, const LocalRun& run);
  // Samples after mark.last_idx, at most `limit`; last_idx becomes the last one sent.
  std::int64_t copy_samples(PgConnection& db, const LocalRun& run, const Watermark& mark,
                            std::int64_t limit, std::int64_t& last_idx);
  std::int64_t copy_events(PgConnection& db, const LocalRun& run, std::int64_t already);
  std::int64_t copy_frames(PgConnection& db, const LocalRun& run, std::int64_t already);
  void copy_channels(PgConnection& db, const LocalRun& run);
  bool already_complete(const LocalRun& run);
  std::int64_t local_samples_after(std::int64_t run_id, std::int64_t after_idx);

  std::string sqlite_path_;
  std::string rig_id_;
  std::string software_version_;
  archive::Database local_;
  std::map<std::string, Watermark> server_;  // by run uuid
  std::set<std::string> complete_;           // runs final and fully on the server
  std::set<std::string> months_ready_;       // "YYYY-MM" whose samples partition exists
  bool server_loaded_ = false;
  bool session_ready_ = false;
};

}  // namespace rig::lab_archive
