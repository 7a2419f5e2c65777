#include "recorder.hpp"

#include <pthread.h>
#include <sched.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>

namespace rig::service {

namespace {
// The recorder drains the loop's rings this often: a sample waits up to this long there.
constexpr std::chrono::milliseconds kDrainPeriod{2};

// A tally's maximum: only the recorder thread writes it, the API reads it.
void raise_to(std::atomic<std::int64_t>& max, std::int64_t value) {
  if (value > max.load(std::memory_order_relaxed)) max.store(value, std::memory_order_relaxed);
}
}  // namespace

std::string describe_fault(rt::FaultCode code, double value) {
  char detail[64] = "";
  switch (code) {
    case rt::FaultCode::kForceLimit:
      std::snprintf(detail, sizeof detail, ": %.3f N", value);
      break;
    case rt::FaultCode::kSoftLimit:
    case rt::FaultCode::kEndLimit:
    case rt::FaultCode::kHomeLimit:
      std::snprintf(detail, sizeof detail, " at %.2f mm", value);
      break;
    case rt::FaultCode::kFollowingError:
      std::snprintf(detail, sizeof detail, ": %.3f mm behind", value);
      break;
    case rt::FaultCode::kLinkLost:
      std::snprintf(detail, sizeof detail, ": no valid reply for %.0f ms", value);
      break;
    case rt::FaultCode::kIopNotSettled:
    case rt::FaultCode::kIopOutOfRange:
      std::snprintf(detail, sizeof detail, ": %.2f mmHg", value);
      break;
    case rt::FaultCode::kHomingFailed:
      std::snprintf(detail, sizeof detail, ": no home switch within %.1f mm of travel", value);
      break;
    case rt::FaultCode::kDaqWriteFailed:
      if (value > 0.0) {
        std::snprintf(detail, sizeof detail, ": %.0f writes in a row lost", value);
      } else {
        std::snprintf(detail, sizeof detail, ": outputs refused by the DAQ");
      }
      break;
    case rt::FaultCode::kDaqWatchdogTripped:
      std::snprintf(detail, sizeof detail, ": outputs were forced off");
      break;
    case rt::FaultCode::kDaqRestarted:
      std::snprintf(detail, sizeof detail, ": conversion counter restarted, outputs reset");
      break;
    default:
      break;
  }
  return std::string(rt::to_string(code)) + detail;
}

Recorder::Recorder(rt::LoopChannels& channels, const std::string& archive_path,
                   int flush_interval_ms, WalSyncer::SyncFunction sync)
    : channels_(&channels),
      archive_(std::make_unique<archive::Archive>(archive_path)),
      flush_interval_ms_(flush_interval_ms),
      cadence_(std::chrono::milliseconds(flush_interval_ms), kDrainPeriod) {
  archive_->defer_checkpoints();
  archive_->defer_log_syncs();  // the syncer makes each commit durable (wal_syncer.hpp)
  syncer_ = std::make_unique<WalSyncer>(archive_path + "-wal", std::move(sync));
  const int interrupted = archive_->recover_interrupted();
  if (interrupted > 0)
    spdlog::warn(
        "archive: {} run(s) were interrupted by the last stop of rigd; their samples are kept",
        interrupted);
  for (const std::string& source : archive_->remove_abandoned_imports()) {
    spdlog::warn(
        "archive: removed a half-imported run of {} (its rig import was stopped before the end); "
        "import the file again",
        source);
  }
}

Recorder::~Recorder() {
  stop();
}

// The syncer at the recorder's priority: a commit is durable only once it has synced.
std::string Recorder::start(int priority) {
  const std::string syncer_refused = syncer_->start(priority);
  thread_ = std::thread([this] { run(); });
  if (priority <= 0) return {};
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param);
  if (rc == 0 && syncer_refused.empty()) return {};
  const std::string refused = rc != 0 ? "SCHED_FIFO priority " + std::to_string(priority) +
                                            " for the recorder refused (" + std::strerror(rc) + ")"
                                      : syncer_refused;
  return refused +
         ": its commits may come late on a busy machine, and a power cut then loses more than one "
         "flush interval";
}

void Recorder::stop() {
  if (!thread_.joinable()) return;
  stop_.store(true);
  thread_.join();
  syncer_->stop();  // syncs the final commit
  tally_synced();
}

void Recorder::add_frames(std::vector<archive::FrameRow> rows) {
  const std::lock_guard lock(frames_mutex_);
  pending_frames_.insert(pending_frames_.end(), std::make_move_iterator(rows.begin()),
                         std::make_move_iterator(rows.end()));
}

void Recorder::flush() {
  if (!dirty_) return;
  archive_->commit();
  dirty_ = false;
  log_to_checkpoint_ = true;
  stats_.commits.fetch_add(1);
}

// A sample is durable once the commit after it has synced. The next commit is due early
// enough that the span from this one's start to the end of the next one's sync stays within
// the flush interval (commit_cadence.hpp): what a power cut can take is then one interval.
// The write is here, the sync on the syncer's thread: a slow sync never delays the next write.
void Recorder::commit_when_due(Clock::time_point& next_commit) {
  const auto began = Clock::now();
  if (began < next_commit) return;
  const bool had_data = dirty_;
  flush();
  const auto ended = Clock::now();
  if (had_data) {
    const Clock::duration late = std::max(Clock::duration::zero(), began - next_commit);
    syncer_->commit_written({began, late, previous_commit_began_});
    raise_to(stats_.max_late_us,
             std::chrono::duration_cast<std::chrono::microseconds>(late).count());
    previous_commit_began_ = began;
    next_commit = cadence_.after_commit(next_commit, began, ended);
  } else {
    previous_commit_began_ =
        began;  // nothing was pending then: later samples are exposed from here
    next_commit = cadence_.after_empty_check(began);
  }
}

// The syncs that ended: a commit's time is its write + sync; its exposure runs from the
// previous commit's start (its oldest sample came after that, having waited up to one drain
// period, ~2 ms, in the loop's ring) to the end of its sync. A failed sync faults the run.
void Recorder::tally_synced() {
  using std::chrono::duration_cast;
  using std::chrono::microseconds;
  for (const WalSyncer::Synced& s : syncer_->take_synced()) {
    if (!s.error.empty()) {
      rt::FaultCode none = rt::FaultCode::kNone;
      if (channels_->service_fault.compare_exchange_strong(none,
                                                           rt::FaultCode::kArchiveWriteFailed))
        spdlog::critical("recorder: {}, faulting the run", s.error);
      continue;
    }
    rt::FaultCode failing = rt::FaultCode::kArchiveWriteFailed;  // writes and syncs work again
    channels_->service_fault.compare_exchange_strong(failing, rt::FaultCode::kNone);
    stats_.durable_commits.fetch_add(s.commits, std::memory_order_relaxed);
    const std::int64_t took_us = duration_cast<microseconds>(s.took).count();
    stats_.last_commit_us.store(took_us, std::memory_order_relaxed);
    raise_to(stats_.max_commit_us, took_us);
    cadence_.note_durable(s.late + s.took);
    if (!s.has_exposure) continue;
    const std::int64_t exposure_us = duration_cast<microseconds>(s.exposure).count();
    stats_.last_exposure_us.store(exposure_us, std::memory_order_relaxed);
    raise_to(stats_.max_exposure_us, exposure_us);
  }
}

// Until 2026-11-28 SQLite copied the log into the database inside whichever commit took it
// past 1000 pages, and a cut's commit could take hundreds of ms (the power-cut test's stalls).
void Recorder::checkpoint_when_idle() {
  constexpr auto kQuietFor = std::chrono::seconds(1);    // no sample for this long: between runs
  constexpr auto kRetryAfter = std::chrono::seconds(1);  // a reader kept part of the log: try again
  const Clock::time_point now = Clock::now();
  if (!log_to_checkpoint_ || dirty_ || open_run_ != 0 || armed_run_ != 0 || !syncer_->idle())
    return;
  if (now - last_sample_ < kQuietFor || now - last_checkpoint_try_ < kRetryAfter) return;
  last_checkpoint_try_ = now;
  const int left = archive_->checkpoint();
  const std::int64_t took_us =
      std::chrono::duration_cast<std::chrono::microseconds>(Clock::now() - now).count();
  stats_.checkpoints.fetch_add(1);
  raise_to(stats_.max_checkpoint_us, took_us);
  log_to_checkpoint_ = left > 0;
}

void Recorder::run() {
  auto next_commit = Clock::now() + std::chrono::milliseconds(flush_interval_ms_);
  while (!stop_.load()) {
    try {
      drain();
      tally_synced();
      commit_when_due(next_commit);
      checkpoint_when_idle();
    } catch (const std::exception& e) {
      // Disk full or I/O error: the loop faults a moving rig at its next cycle; what was
      // committed stays, the failed transaction (< one flush interval) is lost.
      rt::FaultCode none = rt::FaultCode::kNone;
      if (channels_->service_fault.compare_exchange_strong(none,
                                                           rt::FaultCode::kArchiveWriteFailed))
        spdlog::critical("recorder: archive write failed, faulting the run: {}", e.what());
      archive_->rollback();
      dirty_ = false;
      previous_commit_began_ = {};  // the lost transaction is not a commit's exposure
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    std::this_thread::sleep_for(kDrainPeriod);
  }
  try {
    drain();
    const auto began = Clock::now();
    const bool had_data = dirty_;
    flush();
    if (had_data) syncer_->commit_written({began, {}, previous_commit_began_});  // synced by stop()
  } catch (const std::exception& e) {
    spdlog::error("recorder: final flush: {}", e.what());
  }
}

void Recorder::ensure_transaction() {
  if (!dirty_) archive_->begin();
  dirty_ = true;
}

void Recorder::append_waiting_samples() {
  std::size_t count = 0;
  rt::Sample sample;
  while (channels_->recorder.try_pop(sample)) {
    ensure_transaction();
    archive_->append_sample(sample);
    ++count;
  }
  if (count > 0) last_sample_ = Clock::now();
  stats_.samples_written.fetch_add(count);
}

void Recorder::drain() {
  append_waiting_samples();
  rt::Event event;
  while (channels_->recorder_events.try_pop(event)) {
    ensure_transaction();
    handle(event);
  }
  std::vector<archive::FrameRow> frames;
  {
    const std::lock_guard lock(frames_mutex_);
    frames.swap(pending_frames_);
  }
  for (const archive::FrameRow& row : frames) {
    ensure_transaction();
    archive_->add_frame(row);
  }
}

void Recorder::handle(const rt::Event& e) {
  using rt::EventKind;
  switch (e.kind) {
    case EventKind::kCommand:
      if (e.command == rt::CommandKind::kArm && e.result == rt::CommandResult::kAccepted)
        armed_run_ = e.run_id;
      if (e.run_id != 0)
        archive_->add_event(
            e.run_id, e.t_s, "command",
            std::string(rt::to_string(e.command)) + ": " + std::string(rt::to_string(e.result)));
      break;
    case EventKind::kRunStarted:
      open_run_ = e.run_id;
      armed_run_ = 0;
      archive_->mark_started(e.run_id);
      archive_->add_event(e.run_id, e.t_s, "run_started", "cutting started");
      break;
    case EventKind::kRunEnded: {
      // The loop pushes a cycle's sample before that cycle's events, so the run's last sample
      // (the cycle that ended it) is in the ring now: it goes into the same commit as the end.
      append_waiting_samples();
      const bool faulted = e.fault != rt::FaultCode::kNone;
      const std::string outcome = faulted ? "fault" : (e.value > 0.5 ? "stopped" : "completed");
      const std::string reason =
          faulted ? last_fault_ : (e.value > 0.5 ? "stopped by the operator" : "");
      archive_->finish_run(e.run_id, outcome, reason);
      archive_->add_event(e.run_id, e.t_s, "run_ended", outcome);
      open_run_ = 0;
      break;
    }
    case EventKind::kFault:
      last_fault_ = describe_fault(e.fault, e.value);
      if (const std::int64_t id = open_run_ != 0 ? open_run_ : armed_run_)
        archive_->add_event(id, e.t_s, "fault", describe_fault(e.fault, e.value));
      spdlog::error("fault: {}", describe_fault(e.fault, e.value));
      break;
    case EventKind::kStateChanged:
      if (e.from == rt::RunState::kArmed && e.to != rt::RunState::kCutting && armed_run_ != 0) {
        archive_->finish_run(
            armed_run_, "cancelled",
            "left Armed for " + std::string(rt::to_string(e.to)) + " before cutting");
        armed_run_ = 0;
      }
      if (const std::int64_t id = open_run_ != 0 ? open_run_ : armed_run_) {
        archive_->add_event(
            id, e.t_s, "state",
            std::string(rt::to_string(e.from)) + " -> " + std::string(rt::to_string(e.to)));
      }
      spdlog::info("state {} -> {}", rt::to_string(e.from), rt::to_string(e.to));
      break;
    default:
      if (const std::int64_t id = open_run_ != 0 ? open_run_ : armed_run_) {
        char value[32];
        std::snprintf(value, sizeof value, "%.4g", e.value);
        archive_->add_event(id, e.t_s, std::string(rt::to_string(e.kind)), value);
      }
      break;
  }
}

}  // namespace rig::service
