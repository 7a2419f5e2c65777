#pragma once
// [lab_archive] of rigd's config (rig/config/lab_archive_section.hpp) turned into libpq parameters.
#include <string>

#include "pg_connection.hpp"
#include "rig/config/lab_archive_section.hpp"

namespace rig::lab_archive {

using LabArchiveSettings = config::LabArchiveSection;

// libpq keywords: the connection string (as dbname, which libpq expands; later keywords
// override it) with sslmode, the password, keepalives and time-outs so a cut network is
// noticed within seconds. Throws LabArchiveError naming the password file if it cannot be
// read or others may read it.
ConnectionParams connection_params(const LabArchiveSettings& settings);
std::string default_rig_id();

}  // namespace rig::lab_archive
