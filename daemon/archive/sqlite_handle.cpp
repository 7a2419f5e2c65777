#include "sqlite_handle.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>

namespace rig::archive {
namespace {

[[noreturn]] void fail(sqlite3* db, const std::string& what) {
  throw ArchiveError("archive: " + what + ": " +
                     (db != nullptr ? sqlite3_errmsg(db) : "out of memory"));
}

}  // namespace

Database::Database(const std::string& path, bool read_only) : path_(path) {
  sqlite3* raw = nullptr;
  const int flags = read_only ? SQLITE_OPEN_READONLY : (SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE);
  const int rc = sqlite3_open_v2(path.c_str(), &raw, flags | SQLITE_OPEN_NOMUTEX, nullptr);
  db_.reset(raw);
  if (rc != SQLITE_OK) fail(raw, "cannot open " + path);
  sqlite3_busy_handler(raw, &Database::retry_while_busy, nullptr);
}

// Another connection's write transaction is short (the recorder's flush, one chunk of an
// import). Ask again every millisecond, for up to 5 s: SQLite's own busy timeout backs off to
// 100 ms between tries and loses the race for the lock against a writer that commits and
// begins again at once; a 1 ms poll gets in at the importer's next pause (import_run).
int Database::retry_while_busy(void* /*unused*/, int tries_so_far) noexcept {
  constexpr int kMaxTries = 5000;  // x >= 1 ms
  if (tries_so_far >= kMaxTries) return 0;
  std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return 1;
}

int Database::checkpoint_log() {
  int log_frames = 0, copied_frames = 0;
  const int rc = sqlite3_wal_checkpoint_v2(db_.get(), nullptr, SQLITE_CHECKPOINT_PASSIVE,
                                           &log_frames, &copied_frames);
  if (rc != SQLITE_OK && rc != SQLITE_BUSY) fail(db_.get(), "checkpoint of " + path_);
  return std::max(0, log_frames - copied_frames);
}

void Database::exec(const std::string& sql) {
  char* message = nullptr;
  if (sqlite3_exec(db_.get(), sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message != nullptr ? message : "unknown error";
    sqlite3_free(message);
    throw ArchiveError("archive " + path_ + ": " + text + " (in: " + sql.substr(0, 80) + ")");
  }
}

Statement::Statement(sqlite3* db, const std::string& sql) : db_(db), sql_(sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &raw, nullptr) != SQLITE_OK)
    fail(db, "prepare '" + sql + "'");
  stmt_.reset(raw);
}

Statement& Statement::bind(int index, std::int64_t value) {
  if (sqlite3_bind_int64(stmt_.get(), index, value) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int index, double value) {
  if (sqlite3_bind_double(stmt_.get(), index, value) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int index, const std::string& value) {
  if (sqlite3_bind_text(stmt_.get(), index, value.c_str(), static_cast<int>(value.size()),
                        SQLITE_TRANSIENT) != SQLITE_OK)
    fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int index, std::span<const double> blob) {
  if (sqlite3_bind_blob(stmt_.get(), index, blob.data(), static_cast<int>(blob.size_bytes()),
                        SQLITE_TRANSIENT) != SQLITE_OK)
    fail(db_, "bind");
  return *this;
}
Statement& Statement::bind_null(int index) {
  if (sqlite3_bind_null(stmt_.get(), index) != SQLITE_OK) fail(db_, "bind");
  return *this;
}
Statement& Statement::bind(int index, const std::optional<double>& value) {
  return value ? bind(index, *value) : bind_null(index);
}

bool Statement::step() {
  const int rc = sqlite3_step(stmt_.get());
  if (rc == SQLITE_ROW) return true;
  if (rc == SQLITE_DONE) return false;
  fail(db_, "step '" + sql_.substr(0, 60) + "'");
}

void Statement::run() {
  while (step()) {
  }
  reset();
}

void Statement::reset() {
  sqlite3_reset(stmt_.get());
  sqlite3_clear_bindings(stmt_.get());
}

std::int64_t Statement::integer(int column) const {
  return sqlite3_column_int64(stmt_.get(), column);
}
double Statement::real(int column) const {
  return sqlite3_column_double(stmt_.get(), column);
}
bool Statement::is_null(int column) const {
  return sqlite3_column_type(stmt_.get(), column) == SQLITE_NULL;
}
std::optional<double> Statement::maybe_real(int column) const {
  if (is_null(column)) return std::nullopt;
  return real(column);
}
std::string Statement::text(int column) const {
  const auto* p = sqlite3_column_text(stmt_.get(), column);
  return p != nullptr ? std::string(reinterpret_cast<const char*>(p)) : std::string();
}
std::vector<double> Statement::blob(int column) const {
  const void* p = sqlite3_column_blob(stmt_.get(), column);
  std::vector<double> values(blob_bytes(column) / sizeof(double));
  if (!values.empty()) std::memcpy(values.data(), p, values.size() * sizeof(double));
  return values;
}
std::size_t Statement::blob_bytes(int column) const {
  return static_cast<std::size_t>(sqlite3_column_bytes(stmt_.get(), column));
}
}  // namespace rig::archive
