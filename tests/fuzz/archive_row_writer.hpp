#pragma once
// Writes fuzzed rows into an archive that has the product's schema, by raw SQL: every column
// gets whatever the fuzz bytes say (NULL, an integer, any double bit pattern, text that is
// not UTF-8, a blob, a value tens of KB long, a state name the product never writes), so the
// readers see what a damaged, hand-edited or foreign archive can hold. SQLite keeps a value
// of the "wrong" type in a typed column (type affinity only converts what converts cleanly);
// rows that break NOT NULL or a primary key are skipped (INSERT OR IGNORE).
#include <sqlite3.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "fuzz_byte_reader.hpp"

namespace rig::fuzz {

class ArchiveRowWriter {
 public:
  // frame_files: paths a frame row may name (fixed: a fuzzed path could name a FIFO).
  ArchiveRowWriter(sqlite3* db, FuzzByteReader& in, std::vector<std::string> frame_files)
      : db_(db), in_(in), frame_files_(std::move(frame_files)) {}

  // Run ids the rows were given (the readers are asked for these and for every listed run).
  static constexpr std::array<std::int64_t, 6> kRunIds = {
      1, 2, 3, 0, -1, std::numeric_limits<std::int64_t>::max()};

  void write_all() {
    exec("BEGIN");
    const std::size_t runs = 1 + in_.below(3);
    for (std::size_t i = 0; i < runs; ++i) write_run(static_cast<std::int64_t>(i) + 1);
    while (!in_.empty()) {
      switch (in_.below(5)) {
        case 0:
          write_samples();
          break;
        case 1:
          write_meta();
          break;
        case 2:
          write_event();
          break;
        case 3:
          write_channel();
          break;
        default:
          write_frame();
          break;
      }
    }
    exec("COMMIT");
  }

 private:
  struct StatementCloser {
    void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
  };

  void exec(const char* sql) { sqlite3_exec(db_, sql, nullptr, nullptr, nullptr); }

  void insert(const char* sql, int columns,
              void (ArchiveRowWriter::*bind_column)(sqlite3_stmt*, int)) {
    sqlite3_stmt* raw = nullptr;
    if (sqlite3_prepare_v2(db_, sql, -1, &raw, nullptr) != SQLITE_OK)
      __builtin_trap();  // the schema changed
    std::unique_ptr<sqlite3_stmt, StatementCloser> statement(raw);
    for (int c = 1; c <= columns; ++c) (this->*bind_column)(raw, c);
    sqlite3_step(raw);
  }

  // Any value: the first byte picks its kind.
  void bind_any(sqlite3_stmt* s, int index) {
    static const char* const kWords[] = {"rig",
                                         "imported",
                                         "importing",
                                         "completed",
                                         "recording",
                                         "armed",
                                         "interrupted",
                                         "fault",
                                         "",
                                         "2026-11-24T10:00:00.000Z",
                                         "{\"a\":1}",
                                         "{\"k\":[1,",
                                         "\xff\xfe\xc3",
                                         "-1",
                                         "1e308",
                                         "NaN",
                                         "-Infinity",
                                         "9223372036854775808",
                                         "0x10",
                                         " 12 ",
                                         "1,2",
                                         "\\N",
                                         "a\nb\r\\"};
    switch (in_.below(10)) {
      case 0:
        sqlite3_bind_null(s, index);
        break;
      case 1:
        sqlite3_bind_int64(s, index, static_cast<std::int64_t>(in_.byte()) - 8);
        break;
      case 2:
        sqlite3_bind_int64(s, index, static_cast<std::int64_t>(in_.word()));
        break;
      case 3:
        bind_real(s, index);
        break;
      case 4:
        bind_text(s, index, in_.bytes());
        break;
      case 5:
        bind_text(s, index, in_.stretched(32 * 1024));
        break;
      case 6:
        bind_blob(s, index, in_.bytes());
        break;
      case 7:
        bind_blob(s, index, in_.stretched(32 * 1024));
        break;
      case 8:
        bind_text(s, index, kWords[in_.below(std::size(kWords))]);
        break;
      default:
        sqlite3_bind_double(s, index,
                            static_cast<double>(static_cast<std::int8_t>(in_.byte())) / 4.0);
        break;
    }
  }

  void bind_real(sqlite3_stmt* s, int index) {
    const std::uint64_t bits = in_.word();
    double value = 0.0;
    std::memcpy(&value, &bits, sizeof value);
    sqlite3_bind_double(s, index, value);
  }
  static void bind_text(sqlite3_stmt* s, int index, const std::string& text) {
    sqlite3_bind_text(s, index, text.data(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  }
  static void bind_blob(sqlite3_stmt* s, int index, const std::string& bytes) {
    sqlite3_bind_blob(s, index, bytes.data(), static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
  }

  // Mostly one of the known run ids, so child rows meet their run; sometimes anything.
  void bind_run_id(sqlite3_stmt* s, int index) {
    const std::size_t pick = in_.below(kRunIds.size() + 2);
    if (pick < kRunIds.size()) {
      sqlite3_bind_int64(s, index, kRunIds[pick]);
    } else {
      bind_any(s, index);
    }
  }

  void bind_run_column(sqlite3_stmt* s, int index) {
    if (index == 1) {
      sqlite3_bind_int64(s, index, next_run_id_);
    } else {
      bind_any(s, index);
    }
  }
  void bind_child_column(sqlite3_stmt* s, int index) {
    if (index == 1) {
      bind_run_id(s, index);
    } else {
      bind_any(s, index);
    }
  }

  void write_run(std::int64_t id) {
    next_run_id_ = in_.below(4) == 0 ? kRunIds[in_.below(kRunIds.size())] : id;
    insert(
        "INSERT OR IGNORE INTO runs (id, eye_id, iop_mmHg, velocity_mm_s, depth_mm, hold_s, "
        "post_mortem_h, operator,"
        " notes, config_hash, software_version, surface_mm, rate_hz, created_at, started_at, "
        "ended_at, outcome, reason,"
        " source) VALUES (?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?,?)",
        19, &ArchiveRowWriter::bind_run_column);
  }

  // A few fuzzed samples, or a long run of plain ones after them (idx 0.. as the recorder
  // writes them) so sample counts in the thousands are tried too.
  void write_samples() {
    const char* sql =
        "INSERT OR IGNORE INTO samples (run_id, idx, t_s, position_mm, force_N, iop_mmHg, "
        "velocity_mm_s,"
        " motor_V, pump, state, phase, io_ok) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)";
    if (in_.below(4) != 0) return insert(sql, 12, &ArchiveRowWriter::bind_child_column);
    const std::int64_t run_id = kRunIds[in_.below(3)];
    const std::size_t count =
        1 + static_cast<std::size_t>(in_.byte()) * 16;  // up to ~4,000 samples
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(db_, sql, -1, &raw, nullptr);
    std::unique_ptr<sqlite3_stmt, StatementCloser> statement(raw);
    for (std::size_t i = 0; i < count; ++i) {
      const double t = static_cast<double>(i) * 1e-3;
      sqlite3_bind_int64(raw, 1, run_id);
      sqlite3_bind_int64(raw, 2, static_cast<std::int64_t>(i));
      for (int c = 3; c <= 9; ++c) sqlite3_bind_double(raw, c, t * c);
      for (int c = 10; c <= 12; ++c) sqlite3_bind_int64(raw, c, static_cast<std::int64_t>(i % 5));
      sqlite3_step(raw);
      sqlite3_reset(raw);
    }
  }

  void write_meta() {
    insert("INSERT OR IGNORE INTO run_meta (run_id, seq, key, value) VALUES (?,?,?,?)", 4,
           &ArchiveRowWriter::bind_child_column);
  }
  void write_event() {
    insert("INSERT OR IGNORE INTO events (run_id, t_s, kind, message) VALUES (?,?,?,?)", 4,
           &ArchiveRowWriter::bind_child_column);
  }

  // A channel's data is a blob of doubles; here often one of whole doubles, of any count.
  void write_channel() {
    if (in_.below(2) == 0) {
      return insert("INSERT OR IGNORE INTO channels (run_id, name, data) VALUES (?,?,?)", 3,
                    &ArchiveRowWriter::bind_child_column);
    }
    sqlite3_stmt* raw = nullptr;
    sqlite3_prepare_v2(db_, "INSERT OR IGNORE INTO channels (run_id, name, data) VALUES (?,?,?)",
                       -1, &raw, nullptr);
    std::unique_ptr<sqlite3_stmt, StatementCloser> statement(raw);
    bind_run_id(raw, 1);
    bind_text(raw, 2, in_.bytes());
    std::vector<double> values(in_.byte());
    for (auto& v : values) v = static_cast<double>(in_.byte());
    sqlite3_bind_blob(raw, 3, values.data(), static_cast<int>(values.size() * sizeof(double)),
                      SQLITE_TRANSIENT);
    sqlite3_step(raw);
  }

  void bind_frame_column(sqlite3_stmt* s, int index) {
    if (index == 1) return bind_run_id(s, index);
    if (index == 6) return bind_text(s, index, frame_files_[in_.below(frame_files_.size())]);
    bind_any(s, index);
  }
  void write_frame() {
    insert(
        "INSERT OR IGNORE INTO frames (run_id, frame_no, sample_index, camera_ts_ns, host_ts_ns, "
        "file, file_offset,"
        " bytes, width, height) VALUES (?,?,?,?,?,?,?,?,?,?)",
        10, &ArchiveRowWriter::bind_frame_column);
  }

  sqlite3* db_;
  FuzzByteReader& in_;
  std::vector<std::string> frame_files_;
  std::int64_t next_run_id_ = 1;
};

}  // namespace rig::fuzz
