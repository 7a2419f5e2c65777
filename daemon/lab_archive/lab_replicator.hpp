#pragma once
// rigd's store-and-forward to the lab archive: a non-RT thread that reads the local SQLite
// archive (the rig's source of truth; a cut never waits for the network) and ships it with
// RunShipper, reconnecting with back-off after any server or network failure. Its status
// (connected, backlog, last error) is read by `rig status` through the API.
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "lab_archive_settings.hpp"
#include "run_shipper.hpp"

namespace rig::lab_archive {

struct ReplicatorStatus {
  bool enabled = false;
  bool connected = false;
  Backlog backlog;
  std::int64_t samples_shipped = 0;  // since rigd started
  std::string last_error;
  std::string last_shipped_at;  // UTC ISO 8601 of the last pass that shipped anything
  std::string rig_id;
};

// {"rig_id", "connected", "backlog_runs", "backlog_samples", "backlog_known", "samples_shipped",
//  "last_shipped_at", "last_error"}: the "lab_archive" object of rigd's status.
std::string status_json(const ReplicatorStatus& status);

class LabReplicator {
 public:
  LabReplicator(LabArchiveSettings settings, std::string sqlite_path, std::string software_version);
  ~LabReplicator();
  LabReplicator(const LabReplicator&) = delete;
  LabReplicator& operator=(const LabReplicator&) = delete;
  void start();
  void stop();
  ReplicatorStatus status() const;

 private:
  void run();
  // One shipping pass (connecting first if needed); returns the samples shipped.
  std::int64_t pass(std::unique_ptr<PgConnection>& db);
  void wait(int milliseconds);
  void record_failure(const std::string& error, bool was_connected);

  LabArchiveSettings settings_;
  std::string sqlite_path_;
  std::string software_version_;
  std::unique_ptr<RunShipper> shipper_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  ReplicatorStatus status_;
  bool stopping_ = false;
  std::thread thread_;
};

}  // namespace rig::lab_archive
