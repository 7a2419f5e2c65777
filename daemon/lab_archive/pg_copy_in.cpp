#include "pg_copy_in.hpp"

#include <utility>

namespace rig::lab_archive {

PgCopyIn::PgCopyIn(PgConnection& db, const std::string& copy_sql, std::string what)
    : db_(db), what_(std::move(what)) {
  db_.copy_begin(copy_sql, what_);
}

PgCopyIn::~PgCopyIn() {
  if (!done_) db_.copy_abandon("lab archive: " + what_ + ": abandoned by the client");
}

void PgCopyIn::put(std::string_view piece) {
  db_.copy_put(piece, what_);
}

void PgCopyIn::finish() {
  done_ = true;  // after a failed end the COPY is over on the server either way
  db_.copy_end(what_);
}

}  // namespace rig::lab_archive
