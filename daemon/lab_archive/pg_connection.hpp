#pragma once
// A libpq connection with RAII results and COPY FROM STDIN. Errors throw LabArchiveError
// naming what was being done and libpq's message; the connection string is never printed
// (it may carry a password).
#include <libpq-fe.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace rig::lab_archive {

class LabArchiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// libpq keyword/value pairs; a "dbname" holding a connection string or URI is expanded.
using ConnectionParams = std::vector<std::pair<std::string, std::string>>;

struct ResultDeleter {
  void operator()(PGresult* result) const { PQclear(result); }
};

// A query's rows as text (libpq text format); NULL reads as "" with is_null() true.
class PgResult {
 public:
  explicit PgResult(PGresult* result) : result_(result) {}
  int rows() const { return PQntuples(result_.get()); }
  bool is_null(int row, int column) const { return PQgetisnull(result_.get(), row, column) != 0; }
  std::string text(int row, int column) const { return PQgetvalue(result_.get(), row, column); }
  const char* raw(int row, int column) const { return PQgetvalue(result_.get(), row, column); }
  long long integer(int row, int column) const;
  double real(int row, int column) const;

 private:
  std::string bad_value(int row, int column, const char* expected) const;
  std::unique_ptr<PGresult, ResultDeleter> result_;
};

class PgConnection {
 public:
  // conninfo: libpq keyword=value string or postgresql:// URI. Throws if it cannot connect.
  explicit PgConnection(const std::string& conninfo);
  explicit PgConnection(const ConnectionParams& params);
  bool ok() const;
  void exec(const std::string& sql, const std::string& what);
  PgResult query(const std::string& sql, const std::vector<std::string>& params,
                 const std::string& what);
  // As query(), with nullptr for SQL NULL.
  PgResult query_raw(const std::string& sql, const std::vector<const char*>& params,
                     const std::string& what);
  // COPY ... FROM STDIN with the given text-format payload (tab-separated, \N = NULL).
  void copy_in(const std::string& copy_sql, const std::string& payload, const std::string& what);
  // The same in pieces (PgCopyIn wraps these): start, send any number of pieces, end. A COPY
  // abandoned (copy_abandon) fails on the server, and so does its transaction.
  void copy_begin(const std::string& copy_sql, const std::string& what);
  void copy_put(std::string_view piece, const std::string& what);
  void copy_end(const std::string& what);
  void copy_abandon(const std::string& reason) noexcept;
  std::string server_version() const;

 private:
  [[noreturn]] void fail(const std::string& what, PGresult* result = nullptr) const;
  struct ConnDeleter {
    void operator()(PGconn* conn) const { PQfinish(conn); }
  };
  std::unique_ptr<PGconn, ConnDeleter> conn_;
};

// A transaction: BEGIN now, ROLLBACK unless commit() was called.
class PgTransaction {
 public:
  explicit PgTransaction(PgConnection& db) : db_(db) { db_.exec("BEGIN", "begin a transaction"); }
  ~PgTransaction();
  PgTransaction(const PgTransaction&) = delete;
  PgTransaction& operator=(const PgTransaction&) = delete;
  void commit();

 private:
  PgConnection& db_;
  bool done_ = false;
};

}  // namespace rig::lab_archive
