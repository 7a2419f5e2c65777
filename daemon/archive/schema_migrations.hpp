#pragma once
// The archive's schema version (SQLite `PRAGMA user_version`) and the forward migrations
// that bring an older archive up to it. Version 0 is an archive written before versions
// existed; each migration is idempotent SQL, so it is safe on any of those. An archive
// from a newer rigd is refused (never downgraded): its name and both versions are given.
#include <string_view>

#include "sqlite_handle.hpp"

namespace rig::archive {

class SchemaMigrations {
 public:
  static constexpr int kCurrentVersion = 2;

  // Applies every migration above the archive's version, each in its own write transaction
  // (BEGIN IMMEDIATE: two processes opening one old archive migrate it once). Throws ArchiveError.
  static void bring_up_to_date(Database& db);
  // Read-only opens: throws ArchiveError if the archive is newer than this rigd.
  static void check_readable(Database& db);
  static int version_of(Database& db);

 private:
  static std::string_view migration_sql(int to_version);
};

}  // namespace rig::archive
