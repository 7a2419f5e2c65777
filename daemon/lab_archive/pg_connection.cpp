#include "pg_connection.hpp"

#include <charconv>
#include <cstdlib>

namespace rig::lab_archive {

// "column 'samples' of row 3: 'abc' is not an integer" (the value cut to 40 bytes).
std::string PgResult::bad_value(int row, int column, const char* expected) const {
  const char* name = PQfname(result_.get(), column);
  return "lab archive: column '" + std::string(name != nullptr ? name : "?") + "' of row " +
         std::to_string(row) + ": '" + std::string(raw(row, column)).substr(0, 40) + "' is not " +
         expected;
}

long long PgResult::integer(int row, int column) const {
  const char* text = raw(row, column);
  long long value = 0;
  const char* end = text + std::char_traits<char>::length(text);
  if (std::from_chars(text, end, value).ec != std::errc{})
    throw LabArchiveError(bad_value(row, column, "an integer"));
  return value;
}

double PgResult::real(int row, int column) const {
  const char* text = raw(row, column);
  char* end = nullptr;
  const double value =
      std::strtod(text, &end);  // also reads NaN and Infinity as PostgreSQL prints them
  if (end == text) throw LabArchiveError(bad_value(row, column, "a number"));
  return value;
}

PgConnection::PgConnection(const std::string& conninfo)
    : PgConnection(ConnectionParams{{"dbname", conninfo}}) {}

PgConnection::PgConnection(const ConnectionParams& params) {
  std::vector<const char*> keywords, values;
  for (const auto& [keyword, value] : params) {
    keywords.push_back(keyword.c_str());
    values.push_back(value.c_str());
  }
  keywords.push_back(nullptr);
  values.push_back(nullptr);
  conn_.reset(PQconnectdbParams(keywords.data(), values.data(), 1));
  if (!conn_) throw LabArchiveError("lab archive: out of memory while connecting");
  if (PQstatus(conn_.get()) != CONNECTION_OK) fail("connect to the lab archive");
  exec("SET client_min_messages = warning", "quiet notices");
}

bool PgConnection::ok() const {
  return conn_ && PQstatus(conn_.get()) == CONNECTION_OK;
}

std::string PgConnection::server_version() const {
  return std::to_string(PQserverVersion(conn_.get()));
}

void PgConnection::fail(const std::string& what, PGresult* result) const {
  std::string message =
      result != nullptr ? PQresultErrorMessage(result) : PQerrorMessage(conn_.get());
  if (result != nullptr) PQclear(result);
  while (!message.empty() && (message.back() == '\n' || message.back() == ' ')) message.pop_back();
  throw LabArchiveError("lab archive: " + what + ": " + message);
}

void PgConnection::exec(const std::string& sql, const std::string& what) {
  PGresult* result = PQexec(conn_.get(), sql.c_str());
  const ExecStatusType status = result != nullptr ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) fail(what, result);
  PQclear(result);
}

PgResult PgConnection::query(const std::string& sql, const std::vector<std::string>& params,
                             const std::string& what) {
  std::vector<const char*> values;
  values.reserve(params.size());
  for (const auto& p : params) values.push_back(p.c_str());
  return query_raw(sql, values, what);
}

PgResult PgConnection::query_raw(const std::string& sql, const std::vector<const char*>& values,
                                 const std::string& what) {
  PGresult* result = PQexecParams(conn_.get(), sql.c_str(), static_cast<int>(values.size()),
                                  nullptr, values.data(), nullptr, nullptr, 0);
  const ExecStatusType status = result != nullptr ? PQresultStatus(result) : PGRES_FATAL_ERROR;
  if (status != PGRES_COMMAND_OK && status != PGRES_TUPLES_OK) fail(what, result);
  return PgResult(result);
}

void PgConnection::copy_in(const std::string& copy_sql, const std::string& payload,
                           const std::string& what) {
  copy_begin(copy_sql, what);
  copy_put(payload, what);
  copy_end(what);
}

void PgConnection::copy_begin(const std::string& copy_sql, const std::string& what) {
  PGresult* start = PQexec(conn_.get(), copy_sql.c_str());
  if (start == nullptr || PQresultStatus(start) != PGRES_COPY_IN) fail(what, start);
  PQclear(start);
}

void PgConnection::copy_put(std::string_view piece, const std::string& what) {
  if (!piece.empty() &&
      PQputCopyData(conn_.get(), piece.data(), static_cast<int>(piece.size())) != 1)
    fail(what);
}

void PgConnection::copy_end(const std::string& what) {
  if (PQputCopyEnd(conn_.get(), nullptr) != 1) fail(what);
  PGresult* end = PQgetResult(conn_.get());
  const bool copied = end != nullptr && PQresultStatus(end) == PGRES_COMMAND_OK;
  if (!copied) {
    while (PGresult* extra = PQgetResult(conn_.get())) PQclear(extra);
    fail(what, end);
  }
  PQclear(end);
  while (PGresult* extra = PQgetResult(conn_.get())) PQclear(extra);
}

void PgConnection::copy_abandon(const std::string& reason) noexcept {
  if (!ok() || PQputCopyEnd(conn_.get(), reason.c_str()) != 1)
    return;  // a broken connection is dropped by its owner
  while (PGresult* result = PQgetResult(conn_.get())) PQclear(result);
}

PgTransaction::~PgTransaction() {
  if (done_ || !db_.ok()) return;
  try {
    db_.exec("ROLLBACK", "roll back");
  } catch (const LabArchiveError&) {
    // the connection broke: the server rolls the transaction back by itself
  }
}

void PgTransaction::commit() {
  db_.exec("COMMIT", "commit");
  done_ = true;
}

}  // namespace rig::lab_archive
