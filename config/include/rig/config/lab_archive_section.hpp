#pragma once
// [lab_archive] of rigd's config: the lab's PostgreSQL that rigd's replicator ships the
// local archive to (docs/lab-archive.md). Off by default.
#include <string>

namespace rig::config {

struct LabArchiveSection {
  bool enabled = false;  // off: the rig keeps its SQLite archive only
  std::string conninfo;  // libpq connection string or postgresql:// URI, without the password
  std::string
      password_file;  // file holding the password (owner-only: mode 0600 or 0400); empty = none
  std::string sslmode =
      "prefer";           // libpq sslmode: disable, allow, prefer, require, verify-ca, verify-full
  std::string rig_id;     // this rig's name in the lab; empty = host name
  int interval_ms = 200;  // pause between passes when nothing is waiting [ms]
  int batch_samples = 50000;  // most samples per pass [samples]
  int retry_max_ms = 5000;    // longest wait between reconnection attempts [ms]
};

}  // namespace rig::config
