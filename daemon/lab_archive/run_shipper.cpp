#include "run_shipper.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <optional>

#include "binary_copy_rows.hpp"
#include "copy_buffer.hpp"
#include "lab_schema.hpp"
#include "pg_copy_in.hpp"
#include "run_uuid.hpp"

namespace rig::lab_archive {
namespace {

bool is_final(const std::string& outcome) {
  return outcome != "armed" && outcome != "recording";
}

std::string optional_text(archive::Statement& q, int column) {
  return q.is_null(column) ? std::string() : q.text(column);
}

const char* nullable(const std::string& value) {
  return value.empty() ? nullptr : value.c_str();
}

constexpr const char* kUpsertRun = R"sql(
INSERT INTO runs (run_uuid, rig_id, local_run_id, eye_id, iop_mmhg, velocity_mm_s, depth_mm, hold_s, post_mortem_h,
  operator, notes, config_hash, software_version, surface_mm, rate_hz, created_at, started_at, ended_at, outcome,
  reason, source, meta, eye_lot)
VALUES ($1,$2,$3,$4,$5,$6,$7,$8,$9,$10,$11,$12,$13,$14,$15,$16,$17,$18,$19,$20,$21,$22::jsonb,$22::jsonb->>'eye_lot')
ON CONFLICT (run_uuid) DO UPDATE SET started_at = EXCLUDED.started_at, ended_at = EXCLUDED.ended_at,
  outcome = EXCLUDED.outcome, reason = EXCLUDED.reason, meta = EXCLUDED.meta, eye_lot = EXCLUDED.eye_lot,
  replicated_at = now()
RETURNING last_idx, events, frames, xmax = 0,
  (extract(epoch FROM created_at) * 1000000)::bigint - 946684800000000
)sql";

// The samples table's columns, in the order copy_samples sends them (binary COPY).
constexpr const char* kCopySamples =
    "COPY samples (run_uuid, run_created_at, idx, t_s, position_mm, force_n, iop_mmhg, "
    "velocity_mm_s, motor_v, pump,"
    " state, phase, io_ok) FROM STDIN WITH (FORMAT binary)";
constexpr std::int16_t kSampleColumns = 13;
// A COPY goes out in pieces of about this size [bytes]: the server stores one piece while
// the next is read, and a batch never sits in memory whole (about 150 bytes per sample).
constexpr std::size_t kCopyPieceBytes = 1 << 20;

}  // namespace

RunShipper::RunShipper(std::string sqlite_path, std::string rig_id, std::string software_version)
    : sqlite_path_(std::move(sqlite_path)),
      rig_id_(std::move(rig_id)),
      software_version_(std::move(software_version)),
      local_(sqlite_path_, true) {}

void RunShipper::forget_server_state() {
  months_ready_.clear();   // a restored server may lack a partition
  server_loaded_ = false;  // the last known marks still estimate the backlog meanwhile
  session_ready_ = false;
}

void RunShipper::prepare_session(PgConnection& db) {
  if (session_ready_) return;
  db.query(
      "INSERT INTO rigs (rig_id, software_version) VALUES ($1, $2) ON CONFLICT (rig_id) DO UPDATE "
      "SET "
      "last_seen = now(), software_version = EXCLUDED.software_version",
      {rig_id_, software_version_}, "register rig " + rig_id_);
  session_ready_ = true;
}

void RunShipper::load_server_state(PgConnection& db) {
  PgResult rows =
      db.query("SELECT run_uuid, last_idx, events, frames, outcome FROM runs WHERE rig_id = $1",
               {rig_id_}, "read the watermarks of rig " + rig_id_);
  server_.clear();
  for (int r = 0; r < rows.rows(); ++r) {
    server_[rows.text(r, 0)] =
        Watermark{rows.integer(r, 1), rows.integer(r, 2), rows.integer(r, 3), rows.text(r, 4)};
  }
  server_loaded_ = true;
}

std::vector<RunShipper::LocalRun> RunShipper::local_runs() {
  std::vector<LocalRun> runs;
  archive::Statement q = local_.prepare(
      "SELECT id, created_at, outcome, source FROM runs WHERE outcome <> 'armed' ORDER BY id");
  while (q.step()) {
    LocalRun run{q.integer(0), q.text(1), q.text(2), q.text(3), {}};
    run.uuid = lab_run_uuid(rig_id_, run.id, run.created_at);
    runs.push_back(std::move(run));
  }
  return runs;
}

std::int64_t RunShipper::ship_pass(PgConnection& db, std::int64_t max_samples) {
  prepare_session(db);
  if (!server_loaded_) load_server_state(db);
  std::int64_t shipped = 0;
  for (const LocalRun& run : local_runs()) {
    if (complete_.count(run.uuid) != 0) continue;
    if (already_complete(run)) {
      complete_.insert(run.uuid);
      continue;
    }
    shipped += ship_run(db, run, max_samples - shipped);
    if (shipped >= max_samples) break;
  }
  return shipped;
}

std::int64_t RunShipper::ship_run(PgConnection& db, const LocalRun& run, std::int64_t max_samples) {
  const auto known = server_.find(run.uuid);
  Watermark mark = known == server_.end() ? Watermark{} : known->second;
  const std::string month = run.created_at.substr(0, 7);
  if (mark.outcome.empty() && months_ready_.count(month) == 0) {
    ensure_samples_partition(db, run.created_at);
    months_ready_.insert(month);
  }
  PgTransaction tx(db);
  mark = upsert_run(db, run);  // locks the run's row: the watermark read is the one to extend
  if (mark.new_on_server && run.source != "rig") copy_channels(db, run);
  std::int64_t last_idx = mark.last_idx;
  const std::int64_t samples =
      copy_samples(db, run, mark, std::max<std::int64_t>(max_samples, 1), last_idx);
  const std::int64_t events = copy_events(db, run, mark.events);
  const std::int64_t frames = copy_frames(db, run, mark.frames);
  db.query(
      "UPDATE runs SET last_idx = $2, samples = samples + $3, events = events + $4, frames = "
      "frames + $5 "
      "WHERE run_uuid = $1",
      {run.uuid, std::to_string(last_idx), std::to_string(samples), std::to_string(events),
       std::to_string(frames)},
      "advance the watermark of run " + run.uuid);
  tx.commit();
  server_[run.uuid] = Watermark{last_idx, mark.events + events, mark.frames + frames, run.outcome};
  if (is_final(run.outcome) && local_samples_after(run.id, last_idx) == 0)
    complete_.insert(run.uuid);
  return samples;
}

RunShipper::Watermark RunShipper::upsert_run(PgConnection& db, const LocalRun& run) {
  archive::Statement q = local_.prepare(
      "SELECT eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, operator, notes, "
      "config_hash,"
      " software_version, surface_mm, rate_hz, created_at, started_at, ended_at, outcome, reason, "
      "source FROM runs WHERE id = ?");
  q.bind(1, run.id);
  if (!q.step())
    throw archive::ArchiveError(sqlite_path_ + ": run " + std::to_string(run.id) + " vanished");
  std::vector<std::string> values{run.uuid, rig_id_, std::to_string(run.id)};
  for (int column = 0; column < 18; ++column) values.push_back(optional_text(q, column));
  nlohmann::json meta = nlohmann::json::object();
  archive::Statement extra =
      local_.prepare("SELECT key, value FROM run_meta WHERE run_id = ? ORDER BY seq");
  extra.bind(1, run.id);
  while (extra.step()) meta[extra.text(0)] = extra.text(1);
  values.push_back(meta.dump());
  // Parameters that are NOT NULL on the server: uuid, rig, local id, eye_id, surface_mm,
  // created_at, outcome, source, meta. Every other empty text is NULL.
  constexpr std::size_t kRequired[] = {0, 1, 2, 3, 13, 15, 18, 20, 21};
  std::vector<const char*> raw;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const bool required =
        std::find(std::begin(kRequired), std::end(kRequired), i) != std::end(kRequired);
    raw.push_back(required ? values[i].c_str() : nullable(values[i]));
  }
  PgResult mark = db.query_raw(kUpsertRun, raw, "store the metadata of run " + run.uuid);
  return Watermark{mark.integer(0, 0), mark.integer(0, 1),     mark.integer(0, 2),
                   run.outcome,        mark.text(0, 3) == "t", mark.integer(0, 4)};
}

std::int64_t RunShipper::copy_samples(PgConnection& db, const LocalRun& run, const Watermark& mark,
                                      std::int64_t limit, std::int64_t& last_idx) {
  archive::Statement q = local_.prepare(
      "SELECT idx, t_s, position_mm, force_N, iop_mmHg, velocity_mm_s, motor_V, pump, state, "
      "phase, io_ok"
      " FROM samples WHERE run_id = ? AND idx > ? ORDER BY idx LIMIT ?");
  q.bind(1, run.id).bind(2, mark.last_idx).bind(3, limit);
  BinaryCopyRows rows;
  std::optional<PgCopyIn> copy;  // opened with the first full piece: an empty batch sends nothing
  const std::string what = "copy the samples of run " + run.uuid;
  const std::string uuid = BinaryCopyRows::uuid_bytes(run.uuid);
  while (q.step()) {
    last_idx = q.integer(0);
    rows.begin_row(kSampleColumns);
    rows.field_uuid(uuid).field_timestamptz(mark.created_at_us).field(last_idx);
    for (int column = 1; column <= 3; ++column) rows.field(q.real(column));
    for (int column = 4; column <= 7; ++column) rows.field(q.maybe_real(column));
    for (int column = 8; column <= 10; ++column)
      q.is_null(column) ? rows.null() : rows.field_int16(q.integer(column));
    if (rows.pending_bytes() < kCopyPieceBytes) continue;
    if (!copy) copy.emplace(db, kCopySamples, what);
    copy->put(rows.take());
  }
  if (rows.rows() == 0) return 0;
  // The locked watermark says none of these is on the server yet; the primary key would
  // refuse (and roll back) a duplicate if it ever were.
  rows.finish();
  if (!copy) copy.emplace(db, kCopySamples, what);
  copy->put(rows.take());
  copy->finish();
  return rows.rows();
}

std::int64_t RunShipper::copy_events(PgConnection& db, const LocalRun& run, std::int64_t already) {
  archive::Statement q = local_.prepare(
      "SELECT t_s, kind, message FROM events WHERE run_id = ? ORDER BY rowid LIMIT -1 OFFSET ?");
  q.bind(1, run.id).bind(2, already);
  CopyBuffer rows;
  for (std::int64_t seq = already; q.step(); ++seq) {
    rows.field(run.uuid).field(seq).field(q.real(0)).field(q.text(1)).field(q.text(2)).end_row();
  }
  if (rows.rows() == 0) return 0;
  db.copy_in("COPY events FROM STDIN", rows.text(), "copy the events of run " + run.uuid);
  return rows.rows();
}

std::int64_t RunShipper::copy_frames(PgConnection& db, const LocalRun& run, std::int64_t already) {
  archive::Statement q = local_.prepare(
      "SELECT frame_no, sample_index, camera_ts_ns, host_ts_ns, file, file_offset, bytes, width, "
      "height FROM frames"
      " WHERE run_id = ? ORDER BY frame_no LIMIT -1 OFFSET ?");
  q.bind(1, run.id).bind(2, already);
  CopyBuffer rows;
  while (q.step()) {
    rows.field(run.uuid);
    for (int column = 0; column <= 3; ++column) rows.field(q.integer(column));
    rows.field(q.text(4));
    for (int column = 5; column <= 8; ++column) rows.field(q.integer(column));
    rows.end_row();
  }
  if (rows.rows() == 0) return 0;
  db.copy_in("COPY frames FROM STDIN", rows.text(), "copy the frame index of run " + run.uuid);
  return rows.rows();
}

void RunShipper::copy_channels(PgConnection& db, const LocalRun& run) {
  archive::Statement q =
      local_.prepare("SELECT name, data FROM channels WHERE run_id = ? ORDER BY rowid");
  q.bind(1, run.id);
  CopyBuffer rows;
  for (std::int64_t seq = 0; q.step(); ++seq) {
    std::string array = "{";
    CopyBuffer numbers;
    for (const double value : q.blob(1)) numbers.field(value);
    for (const char c : numbers.text()) array += c == '\t' ? ',' : c;
    rows.field(run.uuid).field(seq).field(q.text(0)).field(array + "}").end_row();
  }
  if (rows.rows() > 0)
    db.copy_in("COPY channels FROM STDIN", rows.text(), "copy the channels of run " + run.uuid);
}

bool RunShipper::already_complete(const LocalRun& run) {
  const auto known = server_.find(run.uuid);
  if (known == server_.end() || !is_final(run.outcome) || known->second.outcome != run.outcome)
    return false;
  if (local_samples_after(run.id, known->second.last_idx) != 0) return false;
  archive::Statement q = local_.prepare(
      "SELECT (SELECT count(*) FROM events WHERE run_id = ?1), (SELECT count(*) FROM frames WHERE "
      "run_id = ?1)");
  q.bind(1, run.id);
  q.step();
  return q.integer(0) == known->second.events && q.integer(1) == known->second.frames;
}

std::int64_t RunShipper::local_samples_after(std::int64_t run_id, std::int64_t after_idx) {
  archive::Statement q =
      local_.prepare("SELECT count(*) FROM samples WHERE run_id = ? AND idx > ?");
  q.bind(1, run_id).bind(2, after_idx);
  q.step();
  return q.integer(0);
}

Backlog RunShipper::backlog() {
  Backlog backlog;
  backlog.known = server_loaded_;
  for (const LocalRun& run : local_runs()) {
    if (complete_.count(run.uuid) != 0) continue;
    const auto known = server_.find(run.uuid);
    const std::int64_t after = known == server_.end() ? -1 : known->second.last_idx;
    const std::int64_t behind = local_samples_after(run.id, after);
    const bool done =
        known != server_.end() && known->second.outcome == run.outcome && is_final(run.outcome);
    if (behind > 0 || !done) ++backlog.runs;
    backlog.samples += behind;
  }
  return backlog;
}

}  // namespace rig::lab_archive
