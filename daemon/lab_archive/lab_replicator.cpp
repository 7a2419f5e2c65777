#include "lab_replicator.hpp"

#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>

#include "archive.hpp"
#include "lab_schema.hpp"

namespace rig::lab_archive {

std::string status_json(const ReplicatorStatus& s) {
  return nlohmann::json{{"rig_id", s.rig_id},
                        {"connected", s.connected},
                        {"backlog_runs", s.backlog.runs},
                        {"backlog_samples", s.backlog.samples},
                        {"backlog_known", s.backlog.known},
                        {"samples_shipped", s.samples_shipped},
                        {"last_shipped_at", s.last_shipped_at},
                        {"last_error", s.last_error}}
      .dump();
}

LabReplicator::LabReplicator(LabArchiveSettings settings, std::string sqlite_path,
                             std::string software_version)
    : settings_(std::move(settings)),
      sqlite_path_(std::move(sqlite_path)),
      software_version_(std::move(software_version)) {
  if (settings_.rig_id.empty()) settings_.rig_id = default_rig_id();
  status_.enabled = true;
  status_.rig_id = settings_.rig_id;
}

LabReplicator::~LabReplicator() {
  stop();
}

void LabReplicator::start() {
  connection_params(settings_);  // a bad password file stops rigd at start, with its name
  thread_ = std::thread([this] { run(); });
}

void LabReplicator::stop() {
  {
    std::lock_guard lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

ReplicatorStatus LabReplicator::status() const {
  std::lock_guard lock(mutex_);
  return status_;
}

void LabReplicator::wait(int milliseconds) {
  std::unique_lock lock(mutex_);
  wake_.wait_for(lock, std::chrono::milliseconds(milliseconds), [this] { return stopping_; });
}

std::int64_t LabReplicator::pass(std::unique_ptr<PgConnection>& db) {
  if (!shipper_)
    shipper_ = std::make_unique<RunShipper>(sqlite_path_, settings_.rig_id, software_version_);
  if (!db) {
    db = std::make_unique<PgConnection>(connection_params(settings_));
    create_or_migrate_lab_schema(*db);
    shipper_->forget_server_state();
    spdlog::info("lab archive: connected (rig {})", settings_.rig_id);
  }
  const std::int64_t shipped = shipper_->ship_pass(*db, settings_.batch_samples);
  const Backlog backlog = shipper_->backlog();
  std::lock_guard lock(mutex_);
  status_.connected = true;
  status_.last_error.clear();
  status_.backlog = backlog;
  status_.samples_shipped += shipped;
  if (shipped > 0) status_.last_shipped_at = archive::utc_now_iso8601();
  return shipped;
}

void LabReplicator::record_failure(const std::string& error, bool was_connected) {
  Backlog backlog;
  try {
    if (shipper_) backlog = shipper_->backlog();
  } catch (const std::exception&) {
    // the local archive is unreadable too: the error below says why the pass failed
  }
  std::lock_guard lock(mutex_);
  if (status_.last_error != error || was_connected) spdlog::warn("{}", error);
  status_.connected = false;
  status_.last_error = error;
  if (shipper_) status_.backlog = backlog;
}

void LabReplicator::run() {
  std::unique_ptr<PgConnection> db;
  int retry_ms = 250;
  for (;;) {
    {
      std::lock_guard lock(mutex_);
      if (stopping_) return;
    }
    std::int64_t backlog_samples = 0;
    bool budget_full = false;  // the pass shipped all it may: more is likely waiting
    try {
      budget_full = pass(db) >= settings_.batch_samples;
      retry_ms = 250;
      backlog_samples = status().backlog.samples;
    } catch (const std::exception& e) {
      record_failure(e.what(), db != nullptr);
      db.reset();  // a broken or half-done session: start clean, re-read the watermarks
      backlog_samples = -1;
    }
    if (backlog_samples < 0) {
      wait(retry_ms);
      // Read by the next failed pass (a pass that succeeds sets it back to 250 ms).
      // NOLINTNEXTLINE(clang-analyzer-deadcode.DeadStores)
      retry_ms = std::min(retry_ms * 2, settings_.retry_max_ms);
    } else if (!budget_full && backlog_samples < settings_.batch_samples) {
      wait(settings_.interval_ms);
    }
  }
}

}  // namespace rig::lab_archive
