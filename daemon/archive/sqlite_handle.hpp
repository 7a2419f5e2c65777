#pragma once
// RAII owners of SQLite's C handles and the one place where a SQLite error becomes an
// exception naming the database and the statement.
#include <sqlite3.h>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

namespace rig::archive {

class ArchiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SqliteCloser {
  void operator()(sqlite3* db) const noexcept { sqlite3_close_v2(db); }
};
struct SqliteFinalizer {
  void operator()(sqlite3_stmt* stmt) const noexcept { sqlite3_finalize(stmt); }
};

class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql);
  Statement& bind(int index, std::int64_t value);
  Statement& bind(int index, double value);
  Statement& bind(int index, const std::string& value);
  Statement& bind(int index, std::span<const double> blob);
  Statement& bind_null(int index);
  Statement& bind(int index, const std::optional<double>& value);
  bool step();  // true while a row is available
  void run();   // step to completion and reset
  void reset();
  std::int64_t integer(int column) const;
  double real(int column) const;
  std::optional<double> maybe_real(int column) const;
  std::string text(int column) const;
  // A blob of doubles, copied: SQLite's blob is not aligned for double. Trailing bytes that
  // make no whole double are left out (blob_bytes() tells).
  std::vector<double> blob(int column) const;
  std::size_t blob_bytes(int column) const;
  bool is_null(int column) const;

 private:
  sqlite3* db_;
  std::unique_ptr<sqlite3_stmt, SqliteFinalizer> stmt_;
  std::string sql_;
};

class Database {
 public:
  Database(const std::string& path, bool read_only);
  void exec(const std::string& sql);
  Statement prepare(const std::string& sql) { return Statement(db_.get(), sql); }
  std::int64_t last_insert_id() const { return sqlite3_last_insert_rowid(db_.get()); }
  const std::string& path() const { return path_; }
  // A PASSIVE checkpoint (copies the write-ahead log into the database as far as readers
  // allow, never waits for them): the log's frames not yet copied afterwards.
  int checkpoint_log();

 private:
  static int retry_while_busy(void* unused, int tries_so_far) noexcept;

  std::unique_ptr<sqlite3, SqliteCloser> db_;
  std::string path_;
};

}  // namespace rig::archive
