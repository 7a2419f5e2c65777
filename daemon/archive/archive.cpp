#include "archive.hpp"

#include <chrono>
#include <cmath>
#include <ctime>

#include "metadata_number.hpp"
#include "schema_migrations.hpp"

namespace rig::archive {

std::string utc_now_iso8601() {
  const auto now = std::chrono::system_clock::now();
  const std::time_t seconds = std::chrono::system_clock::to_time_t(now);
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(now.time_since_epoch()).count() % 1000;
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  char text[40];
  const std::size_t n = std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%S", &utc);
  std::snprintf(text + n, sizeof text - n, ".%03dZ", static_cast<int>(ms));
  return text;
}

Archive::Archive(const std::string& path, bool read_only) : db_(path, read_only) {
  if (read_only) {
    SchemaMigrations::check_readable(db_);
    return;
  }
  // synchronous=FULL: in WAL mode NORMAL syncs the log only at checkpoints, so a power cut
  // rolled back commits rigd had acknowledged (a whole run row and its samples, found by
  // kernel.power_cuts_*). FULL syncs the log at every commit. The recorder's own connection
  // syncs it on a thread of its own instead (defer_log_syncs, service/wal_syncer.hpp).
  db_.exec("PRAGMA journal_mode=WAL; PRAGMA synchronous=FULL; PRAGMA foreign_keys=ON;");
  create_schema();
}

void Archive::defer_checkpoints() {
  db_.exec("PRAGMA wal_autocheckpoint=0;");
}

// NORMAL in WAL mode still syncs the log before each checkpoint and the database after it.
void Archive::defer_log_syncs() {
  db_.exec("PRAGMA synchronous=NORMAL;");
}

void Archive::create_schema() {
  SchemaMigrations::bring_up_to_date(db_);
}

std::int64_t Archive::create_run(const NewRun& run) {
  Statement q = db_.prepare(
      "INSERT INTO runs (eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, "
      "operator, notes,"
      " config_hash, software_version, surface_mm, rate_hz, created_at, outcome, source)"
      " VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,'armed','rig')");
  q.bind(1, run.eye_id).bind(2, run.iop_mmHg).bind(3, run.velocity_mm_s).bind(4, run.depth_mm);
  q.bind(5, run.hold_s).bind(6, run.post_mortem_h).bind(7, run.operator_name).bind(8, run.notes);
  q.bind(9, run.config_hash)
      .bind(10, run.software_version)
      .bind(11, run.surface_mm)
      .bind(12, run.rate_hz);
  q.bind(13, utc_now_iso8601());
  q.run();
  const std::int64_t id = db_.last_insert_id();
  Statement meta = db_.prepare("INSERT INTO run_meta (run_id, seq, key, value) VALUES (?,?,?,?)");
  std::int64_t seq = 0;
  for (const auto& [key, value] : run.meta)
    meta.bind(1, id).bind(2, seq++).bind(3, key).bind(4, value).run();
  return id;
}

void Archive::mark_started(std::int64_t run_id) {
  db_.prepare("UPDATE runs SET outcome='recording', started_at=? WHERE id=?")
      .bind(1, utc_now_iso8601())
      .bind(2, run_id)
      .run();
}

void Archive::discard_unstarted_run(std::int64_t run_id) {
  begin();
  try {
    Statement q = db_.prepare(
        "SELECT COUNT(*) FROM runs WHERE id=? AND outcome='armed' AND NOT EXISTS (SELECT 1 FROM "
        "samples WHERE run_id=?)");
    q.bind(1, run_id).bind(2, run_id);
    const bool unstarted = q.step() && q.integer(0) == 1;
    q.reset();
    if (unstarted) {
      db_.prepare("DELETE FROM run_meta WHERE run_id=?").bind(1, run_id).run();
      db_.prepare("DELETE FROM runs WHERE id=?").bind(1, run_id).run();
    }
    commit();
  } catch (...) {
    rollback();
    throw;
  }
}

void Archive::finish_run(std::int64_t run_id, const std::string& outcome,
                         const std::string& reason) {
  db_.prepare("UPDATE runs SET outcome=?, reason=?, ended_at=? WHERE id=?")
      .bind(1, outcome)
      .bind(2, reason)
      .bind(3, utc_now_iso8601())
      .bind(4, run_id)
      .run();
}

int Archive::recover_interrupted() {
  const auto before = list_runs();
  int count = 0;
  for (const auto& row : before) {
    if (row.outcome == "recording") {
      finish_run(row.id, "interrupted",
                 "rigd stopped while recording; samples up to the last commit are kept");
      ++count;
    } else if (row.outcome == "armed") {
      // Killed while armed: the run was interrupted by the crash, not cancelled by anyone.
      finish_run(row.id, "interrupted", "rigd stopped before the cut started");
      ++count;
    }
  }
  return count;
}

void Archive::begin() {
  if (in_transaction_) return;
  db_.exec("BEGIN");
  in_transaction_ = true;
}

void Archive::commit() {
  if (!in_transaction_) return;
  db_.exec("COMMIT");
  in_transaction_ = false;
}

void Archive::rollback() noexcept {
  try {
    if (in_transaction_) db_.exec("ROLLBACK");
  } catch (const std::exception&) {
    // SQLite may have rolled back by itself already (SQLITE_FULL)
  }
  in_transaction_ = false;
}

void Archive::append_sample(const rt::Sample& s) {
  if (!insert_sample_) {
    insert_sample_.emplace(
        db_.prepare("INSERT OR REPLACE INTO samples (run_id, idx, t_s, position_mm, force_N, "
                    "iop_mmHg, velocity_mm_s,"
                    " motor_V, pump, state, phase, io_ok) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)"));
  }
  Statement& q = *insert_sample_;
  q.bind(1, s.run_id)
      .bind(2, static_cast<std::int64_t>(s.cycle))
      .bind(3, s.t_s)
      .bind(4, s.position_mm);
  q.bind(5, s.force_N)
      .bind(6, s.iop_mmHg)
      .bind(7, s.velocity_mm_s)
      .bind(8, s.motor_volts)
      .bind(9, s.pump_command);
  q.bind(10, static_cast<std::int64_t>(s.state)).bind(11, static_cast<std::int64_t>(s.phase));
  q.bind(12, static_cast<std::int64_t>(s.io_ok));
  q.run();
}

void Archive::add_event(std::int64_t run_id, double t_s, const std::string& kind,
                        const std::string& message) {
  db_.prepare("INSERT INTO events (run_id, t_s, kind, message) VALUES (?,?,?,?)")
      .bind(1, run_id)
      .bind(2, t_s)
      .bind(3, kind)
      .bind(4, message)
      .run();
}

RunRow Archive::read_row(Statement& q) {
  RunRow row;
  row.id = q.integer(0);
  row.eye_id = q.text(1);
  row.iop_mmHg = q.maybe_real(2);
  row.velocity_mm_s = q.maybe_real(3);
  row.depth_mm = q.maybe_real(4);
  row.started_at = q.is_null(5) ? q.text(10) : q.text(5);
  row.ended_at = q.text(6);
  row.outcome = q.text(7);
  row.reason = q.text(8);
  row.source = q.text(9);
  row.samples = q.integer(11);
  return row;
}

std::vector<RunRow> Archive::list_runs() {
  Statement q = db_.prepare(
      "SELECT id, eye_id, iop_mmHg, velocity_mm_s, depth_mm, started_at, ended_at, outcome, "
      "reason, source,"
      " created_at, (SELECT COUNT(*) FROM samples s WHERE s.run_id = runs.id) FROM runs ORDER BY "
      "id");
  std::vector<RunRow> rows;
  while (q.step()) rows.push_back(read_row(q));
  return rows;
}

std::optional<RunRow> Archive::find_run(std::int64_t run_id) {
  Statement q = db_.prepare(
      "SELECT id, eye_id, iop_mmHg, velocity_mm_s, depth_mm, started_at, ended_at, outcome, "
      "reason, source,"
      " created_at, (SELECT COUNT(*) FROM samples s WHERE s.run_id = runs.id) FROM runs WHERE id = "
      "?");
  q.bind(1, run_id);
  if (!q.step()) return std::nullopt;
  return read_row(q);
}

std::vector<std::pair<std::string, std::string>> Archive::run_meta(std::int64_t run_id) {
  std::vector<std::pair<std::string, std::string>> meta;
  Statement q = db_.prepare(
      "SELECT eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, operator, notes,"
      " config_hash, software_version, started_at, outcome, reason, source, surface_mm FROM runs "
      "WHERE id = ?");
  q.bind(1, run_id);
  if (!q.step()) return meta;
  const char* names[] = {
      "eye_id",        "iop_mmHg", "velocity_mm_s", "depth_mm",    "hold_s",
      "post_mortem_h", "operator", "notes",         "config_hash", "software_version",
      "started_at",    "outcome",  "reason",        "source"};
  for (int i = 0; i < 14; ++i) {
    if (q.is_null(i)) continue;
    const bool numeric = i >= 1 && i <= 5;
    std::string value = numeric ? metadata_number_text(q.real(i)) : q.text(i);
    if (!value.empty()) meta.emplace_back(names[i], value);
  }
  meta.emplace_back("run_id", std::to_string(run_id));
  Statement extra = db_.prepare("SELECT key, value FROM run_meta WHERE run_id = ? ORDER BY seq");
  extra.bind(1, run_id);
  while (extra.step()) meta.emplace_back(extra.text(0), extra.text(1));
  return meta;
}

std::vector<EventRow> Archive::run_events(std::int64_t run_id) {
  std::vector<EventRow> events;
  Statement q =
      db_.prepare("SELECT t_s, kind, message FROM events WHERE run_id = ? ORDER BY rowid");
  q.bind(1, run_id);
  while (q.step()) events.push_back({q.real(0), q.text(1), q.text(2)});
  return events;
}

}  // namespace rig::archive
