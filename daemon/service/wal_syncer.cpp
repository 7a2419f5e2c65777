#include "wal_syncer.hpp"

#include <fcntl.h>
#include <pthread.h>
#include <sched.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace rig::service {

namespace {
int data_sync(int fd) {
  return ::fdatasync(fd) == 0 ? 0 : errno;
}

// The log's directory entry is durable too: SQLite syncs the directory after creating a file
// only in its own syncs, which synchronous=NORMAL skips at commits.
int sync_directory_of(const std::string& path) {
  const std::string dir = std::filesystem::path(path).parent_path().string();
  const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return errno;
  const int rc = ::fsync(fd) == 0 ? 0 : errno;
  ::close(fd);
  return rc;
}
}  // namespace

WalSyncer::WalSyncer(std::string log_path, SyncFunction sync)
    : log_path_(std::move(log_path)), sync_(sync ? std::move(sync) : SyncFunction(data_sync)) {
  if (const int rc = open_log(); rc != 0) {
    throw std::runtime_error("archive log " + log_path_ + ": cannot open it to sync commits (" +
                             std::strerror(rc) + ")");
  }
}

WalSyncer::~WalSyncer() {
  stop();
  if (fd_ >= 0) ::close(fd_);
}

int WalSyncer::open_log() {
  const int fd = ::open(log_path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno;
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
  return sync_directory_of(log_path_);
}

std::string WalSyncer::start(int priority) {
  thread_ = std::thread([this] { run(); });
  if (priority <= 0) return {};
  sched_param param{};
  param.sched_priority = priority;
  const int rc = pthread_setschedparam(thread_.native_handle(), SCHED_FIFO, &param);
  if (rc == 0) return {};
  return "SCHED_FIFO priority " + std::to_string(priority) +
         " for the archive's log sync refused (" + std::strerror(rc) + ")";
}

void WalSyncer::stop() {
  {
    const std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  if (thread_.joinable()) thread_.join();
}

void WalSyncer::commit_written(const Commit& commit) {
  {
    const std::lock_guard lock(mutex_);
    written_.push_back(commit);
  }
  wake_.notify_all();
}

std::vector<WalSyncer::Synced> WalSyncer::take_synced() {
  std::vector<Synced> out;
  const std::lock_guard lock(mutex_);
  out.swap(synced_);
  return out;
}

bool WalSyncer::idle() const {
  const std::lock_guard lock(mutex_);
  return written_.empty() && !syncing_;
}

// SQLite keeps its log while a connection is open (the recorder's always is); should it ever
// be replaced (a new inode at the path), the new one is opened, so a sync never misses it.
int WalSyncer::sync_log() {
  struct stat at_path {};
  struct stat open_one {};
  if (::stat(log_path_.c_str(), &at_path) != 0) return errno;
  if (fd_ < 0 || ::fstat(fd_, &open_one) != 0 || open_one.st_ino != at_path.st_ino ||
      open_one.st_dev != at_path.st_dev) {
    if (const int rc = open_log(); rc != 0) return rc;
  }
  return sync_(fd_);
}

void WalSyncer::run() {
  std::unique_lock lock(mutex_);
  while (true) {
    wake_.wait(lock, [this] { return stop_ || !written_.empty(); });
    if (written_.empty()) return;  // stopping, everything synced
    // Every commit written so far goes into this sync; later ones wait for the next.
    const std::size_t count = written_.size();
    const Commit oldest = written_.front();
    syncing_ = true;
    lock.unlock();
    const int rc = sync_log();
    const Clock::time_point ended = Clock::now();
    lock.lock();
    syncing_ = false;
    written_.erase(written_.begin(), written_.begin() + static_cast<std::ptrdiff_t>(count));
    Synced s;
    s.commits = count;
    s.took = ended - oldest.began;
    s.late = oldest.late;
    s.has_exposure = oldest.exposed_since != Clock::time_point{};
    if (s.has_exposure) s.exposure = ended - oldest.exposed_since;
    if (rc != 0) s.error = "syncing the archive log " + log_path_ + " failed: " + std::strerror(rc);
    synced_.push_back(std::move(s));
  }
}

}  // namespace rig::service
