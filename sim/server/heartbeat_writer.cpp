#include "heartbeat_writer.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <stdexcept>
#include <string>

namespace rig::sim {

HeartbeatWriter::HeartbeatWriter(int fd, int period_ms)
    : fd_(fd), period_ns_(static_cast<std::int64_t>(period_ms) * 1'000'000) {
  if (fd_ < 0) return;
  if (period_ms < 1) throw std::invalid_argument("rig-sim: heartbeat period must be at least 1 ms");
  const int flags = fcntl(fd_, F_GETFL);
  if (flags < 0 || fcntl(fd_, F_SETFL, flags | O_NONBLOCK) != 0) {
    throw std::runtime_error("rig-sim: heartbeat descriptor " + std::to_string(fd_) +
                             " is not open");
  }
}

void HeartbeatWriter::note_read_request(std::int64_t now_ns) noexcept {
  last_request_ns_.store(now_ns, std::memory_order_relaxed);
}

void HeartbeatWriter::tick(std::int64_t now_ns) noexcept {
  if (fd_ < 0 || now_ns - last_write_ns_ < period_ns_) return;
  last_write_ns_ = now_ns;
  const std::int64_t request_ns = last_request_ns_.load(std::memory_order_relaxed);
  const long long age_us = request_ns < 0 ? -1 : (now_ns - request_ns) / 1000;
  char line[48];
  const int length = std::snprintf(line, sizeof line, "%lld %lld\n",
                                   static_cast<long long>(now_ns / 1000), age_us);
  // One write: a line either goes whole or (full pipe, tty or socket) not at all, except the
  // rare partial write, which the reader skips as a malformed line.
  if (write(fd_, line, static_cast<std::size_t>(length)) == length) {
    written_.fetch_add(1, std::memory_order_relaxed);
  } else {
    dropped_.fetch_add(1, std::memory_order_relaxed);
  }
}

}  // namespace rig::sim
