// Archive <-> run-CSV data: loading a run for export and the model lab, importing files.
#include <algorithm>
#include <chrono>
#include <thread>

#include "archive.hpp"
#include "import_process.hpp"

namespace rig::archive {

model::RunData Archive::load_run(std::int64_t run_id) {
  model::RunData run;
  run.source = "archive run " + std::to_string(run_id);
  Statement info = db_.prepare("SELECT surface_mm, source FROM runs WHERE id = ?");
  info.bind(1, run_id);
  if (!info.step()) throw ArchiveError("archive " + path() + ": no run " + std::to_string(run_id));
  const double surface_mm = info.real(0);
  const bool from_rig = info.text(1) == "rig";
  run.meta = run_meta(run_id);
  Statement q = db_.prepare(
      "SELECT t_s, position_mm, force_N, iop_mmHg, motor_V, velocity_mm_s FROM samples WHERE "
      "run_id = ? ORDER BY idx");
  q.bind(1, run_id);
  model::Channel iop{"iop_meas_mmHg", {}};
  model::Channel motor{"motor_cmd_V", {}};
  model::Channel velocity{"velocity_meas_mm_s", {}};
  double t0 = 0.0;
  while (q.step()) {
    if (run.t_s.empty()) t0 = from_rig ? q.real(0) : 0.0;
    run.t_s.push_back(q.real(0) - t0);
    run.x_mm.push_back(q.real(1) - surface_mm);
    run.force_N.push_back(q.real(2));
    if (from_rig) {
      iop.values.push_back(q.real(3));
      motor.values.push_back(q.real(4));
      velocity.values.push_back(q.real(5));
    }
  }
  if (from_rig) {
    run.channels = {std::move(iop), std::move(motor), std::move(velocity)};
  } else {
    Statement ch = db_.prepare("SELECT name, data FROM channels WHERE run_id = ? ORDER BY rowid");
    ch.bind(1, run_id);
    while (ch.step()) {
      if (ch.blob_bytes(1) % sizeof(double) != 0) {
        throw ArchiveError("archive " + path() + ": run " + std::to_string(run_id) + ": channel '" +
                           ch.text(0) + "': " + std::to_string(ch.blob_bytes(1)) +
                           " bytes are not a whole number of doubles");
      }
      run.channels.push_back({ch.text(0), ch.blob(1)});
    }
  }
  // The lab and the run-CSV writer index every channel by sample: a channel of another length
  // (a hand-edited or damaged archive) is refused here, naming it.
  if (const auto mismatch = run.channel_length_mismatch()) {
    throw ArchiveError("archive " + path() + ": run " + std::to_string(run_id) + ": " + *mismatch);
  }
  return run;
}

// An import can be millions of rows: it writes them in transactions of at most
// kImportChunk and pauses after each, so rigd's recorder (which asks for the lock every 1 ms,
// Database::retry_while_busy) is never held off longer than one chunk and a running cut never
// faults on a busy archive. The run is 'importing' until its last row is in; a failed import
// removes it again.
std::int64_t Archive::import_run(const model::RunData& run) {
  const std::int64_t id = import_run_row(run);
  try {
    import_samples(id, run);
    begin();
    Statement channel = db_.prepare("INSERT INTO channels (run_id, name, data) VALUES (?,?,?)");
    for (const auto& c : run.channels)
      channel.bind(1, id).bind(2, c.name).bind(3, std::span<const double>(c.values)).run();
    db_.prepare("UPDATE runs SET outcome='imported' WHERE id=?").bind(1, id).run();
    db_.prepare("DELETE FROM run_meta WHERE run_id=? AND key='import_process'").bind(1, id).run();
    commit();
    return id;
  } catch (...) {
    if (in_transaction_) rollback();
    remove_run_rows(id);
    throw;
  }
}

std::int64_t Archive::import_run_row(const model::RunData& run) {
  begin();
  try {
    Statement q = db_.prepare(
        "INSERT INTO runs (eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, post_mortem_h, "
        "operator, notes,"
        " surface_mm, created_at, started_at, ended_at, outcome, source) VALUES "
        "(?,?,?,?,?,?,?,?,0,?,?,?,'importing',?)");
    const std::string now = utc_now_iso8601();
    q.bind(1, run.text("eye_id").value_or(run.source))
        .bind(2, run.number("iop_mmHg"))
        .bind(3, run.number("velocity_mm_s"));
    q.bind(4, run.number("depth_mm"))
        .bind(5, run.number("hold_s"))
        .bind(6, run.number("post_mortem_h"));
    q.bind(7, run.text("operator").value_or("")).bind(8, run.text("notes").value_or(""));
    q.bind(9, now)
        .bind(10, run.text("started_at").value_or(now))
        .bind(11, now)
        .bind(12, run.source);
    q.run();
    const std::int64_t id = db_.last_insert_id();
    const char* columns[] = {"eye_id",     "iop_mmHg",      "velocity_mm_s", "depth_mm",
                             "hold_s",     "post_mortem_h", "operator",      "notes",
                             "started_at", "outcome",       "run_id",        "source"};
    Statement meta = db_.prepare("INSERT INTO run_meta (run_id, seq, key, value) VALUES (?,?,?,?)");
    std::int64_t seq = 0;
    for (const auto& [key, value] : run.meta) {
      if (std::find(std::begin(columns), std::end(columns), key) != std::end(columns)) continue;
      meta.bind(1, id).bind(2, seq++).bind(3, key).bind(4, value).run();
    }
    if (const auto original = run.text("run_id"))
      meta.bind(1, id)
          .bind(2, seq++)
          .bind(3, std::string("original_run_id"))
          .bind(4, *original)
          .run();
    // Until the last row is in: who imports it (remove_abandoned_imports), dropped at the end.
    meta.bind(1, id)
        .bind(2, seq++)
        .bind(3, std::string("import_process"))
        .bind(4, current_import_process())
        .run();
    commit();
    return id;
  } catch (...) {
    rollback();
    throw;
  }
}

void Archive::import_samples(std::int64_t id, const model::RunData& run) {
  using Clock = std::chrono::steady_clock;
  constexpr auto kImportChunk = std::chrono::milliseconds(20);  // longest hold of the write lock
  constexpr auto kPause = std::chrono::milliseconds(3);         // waiting writers get in here
  Statement sample = db_.prepare(
      "INSERT INTO samples (run_id, idx, t_s, position_mm, force_N) VALUES (?,?,?,?,?)");
  std::size_t i = 0;
  while (i < run.size()) {
    begin();
    const auto chunk_start = Clock::now();
    do {
      sample.bind(1, id)
          .bind(2, static_cast<std::int64_t>(i))
          .bind(3, run.t_s[i])
          .bind(4, run.x_mm[i])
          .bind(5, run.force_N[i])
          .run();
      ++i;
    } while (i < run.size() && (i % 256 != 0 || Clock::now() - chunk_start < kImportChunk));
    commit();
    if (i < run.size()) std::this_thread::sleep_for(kPause);
  }
}

std::vector<std::string> Archive::remove_abandoned_imports() {
  std::vector<std::pair<std::int64_t, std::string>> abandoned;
  Statement q = db_.prepare(
      "SELECT r.id, r.source, coalesce(m.value, '') FROM runs r LEFT JOIN run_meta m ON m.run_id = "
      "r.id AND "
      "m.key = 'import_process' WHERE r.outcome = 'importing'");
  while (q.step()) {
    if (!import_process_alive(q.text(2))) abandoned.emplace_back(q.integer(0), q.text(1));
  }
  std::vector<std::string> sources;
  for (const auto& [id, source] : abandoned) {
    remove_run_rows(id);
    sources.push_back(source);
  }
  return sources;
}

void Archive::remove_run_rows(std::int64_t id) noexcept {
  try {
    begin();
    for (const char* table : {"samples", "channels", "run_meta", "events", "frames"}) {
      db_.prepare(std::string("DELETE FROM ") + table + " WHERE run_id=?").bind(1, id).run();
    }
    db_.prepare("DELETE FROM runs WHERE id=?").bind(1, id).run();
    commit();
  } catch (const std::exception&) {  // the import's own error is the one to report
    if (in_transaction_) rollback();
  }
}

}  // namespace rig::archive
