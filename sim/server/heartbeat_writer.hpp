#pragma once
// rig-sim's heartbeat (off by default; `rig-sim --heartbeat-fd`): every period, one text line
// on a file descriptor saying when rig-sim last served a DAQ read, so an observer outside the
// machine (the power-cut test reads it from the VM's second serial port) knows, to within a
// period, how far rigd's loop had come: rigd reads the DAQ once per loop cycle.
//
// Line: "<now_us> <age_us>\n", both on CLOCK_MONOTONIC: now_us when the line was written [us],
// age_us how long before that the last read request arrived [us] (-1: none yet). Short: with a
// tty's \r, 16 bytes or less (a 16550 UART's FIFO, taken in one go) while the uptime is below
// 2.7 h and the age below 1 ms.
// Writes never block: the descriptor is made non-blocking and a line that does not fit is
// dropped (counted), so a stalled reader cannot hold up the DAQ's physics clock.
#include <atomic>
#include <cstdint>

namespace rig::sim {

class HeartbeatWriter {
 public:
  HeartbeatWriter(int fd, int period_ms);  // fd < 0: off; fd is not closed
  bool enabled() const { return fd_ >= 0; }
  void note_read_request(std::int64_t now_ns) noexcept;  // any thread; steady clock [ns]
  void tick(std::int64_t now_ns) noexcept;               // one thread; writes once a period passed
  std::uint64_t written() const { return written_.load(); }
  std::uint64_t dropped() const { return dropped_.load(); }

 private:
  int fd_;
  std::int64_t period_ns_;
  std::int64_t last_write_ns_ = 0;
  std::atomic<std::int64_t> last_request_ns_{-1};
  std::atomic<std::uint64_t> written_{0};
  std::atomic<std::uint64_t> dropped_{0};
};

}  // namespace rig::sim
