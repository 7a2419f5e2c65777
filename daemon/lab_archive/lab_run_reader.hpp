#pragma once
// Reading the lab archive: runs of every rig, filtered (rig, eye lot, since, metadata
// key=value), and a run's data as run-CSV data, exactly as the local archive gives it.
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "pg_connection.hpp"
#include "run_data.hpp"

namespace rig::lab_archive {

struct LabRunFilter {
  std::string rig;
  std::string eye_lot;
  std::string since;  // ISO 8601 date or timestamp: runs created at or after it
  std::string run;    // one run uuid
  std::vector<std::pair<std::string, std::string>>
      meta;  // eye_id, operator, outcome, source or any extra key
  // "rig=R", "eye_lot=L" (or eye-lot), "since=D", "run=UUID", anything else: metadata.
  // Throws naming the argument if it is not key=value.
  void add(const std::string& key_value);
};

struct LabRunRow {
  std::string uuid;
  std::string rig_id;
  std::int64_t local_run_id = 0;
  std::string eye_id;
  std::string eye_lot;
  std::optional<double> iop_mmHg, velocity_mm_s, depth_mm;
  std::string started_at;
  std::string ended_at;
  std::string outcome;
  std::string source;
  std::int64_t samples = 0;
};

class LabRunReader {
 public:
  explicit LabRunReader(const std::string& conninfo);
  explicit LabRunReader(
      const ConnectionParams& params);  // as rigd connects (lab_archive_settings.hpp)
  std::vector<LabRunRow> list_runs(const LabRunFilter& filter);
  model::RunData load_run(const std::string& run_uuid);
  PgConnection& connection() { return db_; }

 private:
  PgConnection db_;
};

}  // namespace rig::lab_archive
