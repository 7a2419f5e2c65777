#pragma once
// The only ways in and out of the RT loop: lock-free rings of samples and events, a
// command queue, the latest status, the jitter histogram and counters. Allocated at setup.
#include <atomic>
#include <cstdint>
#include <mutex>

#include "jitter_histogram.hpp"
#include "latest_value.hpp"
#include "run_types.hpp"
#include "spsc_ring.hpp"
#include "status_snapshot.hpp"

namespace rig::rt {

// Many non-RT producers (API sessions) serialise on a mutex; the RT side only pops.
class CommandQueue {
 public:
  explicit CommandQueue(std::size_t capacity) : ring_(capacity) {}
  bool push(const Command& command) {
    std::lock_guard lock(producer_mutex_);
    return ring_.try_push(command);
  }
  bool pop(Command& command) noexcept { return ring_.try_pop(command); }

 private:
  std::mutex producer_mutex_;
  SpscRing<Command> ring_;
};

struct LoopCounters {
  std::atomic<std::uint64_t> cycles{0};
  std::atomic<std::uint64_t> overruns{0};        // cycles that ended past the next deadline
  std::atomic<std::uint64_t> missed_cycles{0};   // deadlines skipped after overruns
  std::atomic<std::uint64_t> io_misses{0};       // failed DAQ reads
  std::atomic<std::uint64_t> write_failures{0};  // output writes refused while reads succeeded
  std::atomic<std::uint64_t> late_wakes{0};      // cycles the loop began > half a period late
  std::atomic<std::uint64_t> late_wake_misses{
      0};  // failed reads in those: rigd's lateness, not the link's
  std::atomic<std::uint64_t> recorder_drops{0};  // must stay 0: a full ring faults the run
  std::atomic<std::uint64_t> stream_drops{0};    // live view only: dropping is allowed
  std::atomic<std::uint64_t> event_drops{0};
  std::atomic<std::int64_t> start_ns{0};  // loop start on the clock's time line [ns]
};

struct LoopChannels {
  // 2^16 samples = 65 s at 1 kHz of recorder slack.
  explicit LoopChannels(std::size_t sample_capacity = 1U << 16U)
      : recorder(sample_capacity),
        stream(sample_capacity),
        recorder_events(4096),
        stream_events(4096),
        commands(64) {}

  SpscRing<Sample> recorder;
  SpscRing<Sample> stream;
  SpscRing<Event> recorder_events;
  SpscRing<Event> stream_events;
  CommandQueue commands;
  LatestValue<StatusSnapshot> status;
  JitterHistogram jitter;
  LoopCounters counters;
  // Faults found outside the loop (archive writes, camera): services store a FaultCode, the
  // loop reads it every cycle and faults a moving rig. Lock-free, set and cleared by the service.
  std::atomic<FaultCode> service_fault{FaultCode::kNone};
};

}  // namespace rig::rt
