#pragma once
// One COPY ... FROM STDIN sent in pieces: started by the constructor, ended by finish(). If
// it is left unfinished (an exception while the rows were read), the destructor abandons it:
// the server refuses the COPY, so the enclosing transaction stores none of its rows.
#include <string>
#include <string_view>

#include "pg_connection.hpp"

namespace rig::lab_archive {

class PgCopyIn {
 public:
  PgCopyIn(PgConnection& db, const std::string& copy_sql, std::string what);
  ~PgCopyIn();
  PgCopyIn(const PgCopyIn&) = delete;
  PgCopyIn& operator=(const PgCopyIn&) = delete;
  void put(std::string_view piece);
  void finish();

 private:
  PgConnection& db_;
  std::string what_;
  bool done_ = false;
};

}  // namespace rig::lab_archive
