#pragma once
// What the machine itself does to time under load: one thread per CPU, pinned there at
// SCHED_FIFO 99 (when allowed), sleeps 1 ms on absolute deadlines and notes every wake more
// than 5 ms late (docs/loop-timing.md's first measurement noted those over 3 ms). At that priority
// only the machine can hold it: a VM's vCPU throttled by its host, or the kernel. A stall of one
// CPU while another runs is what separates a simulated DAQ from the loop it answers
// (daemon/cli/shared_cpu.hpp); the load tier prints the counts.
#include <pthread.h>
#include <sched.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>
#include <vector>

namespace rig::testing {

class CpuStallProbe {
 public:
  struct Stall {
    std::int64_t woke_ns;  // CLOCK_MONOTONIC at the late wake [ns]
    std::int64_t late_ns;  // how late the wake was [ns]
  };

  CpuStallProbe() {
    cpu_set_t allowed;
    CPU_ZERO(&allowed);
    sched_getaffinity(0, sizeof allowed, &allowed);
    std::vector<int> cpus;
    for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
      if (CPU_ISSET(cpu, &allowed)) cpus.push_back(cpu);
    }
    stalls_.resize(cpus.size());
    for (std::size_t i = 0; i < cpus.size(); ++i)
      threads_.emplace_back([this, i, cpu = cpus[i]] { watch(i, cpu); });
  }
  ~CpuStallProbe() { stop(); }
  CpuStallProbe(const CpuStallProbe&) = delete;
  CpuStallProbe& operator=(const CpuStallProbe&) = delete;

  void stop() {
    stop_.store(true);
    for (auto& t : threads_) {
      if (t.joinable()) t.join();
    }
  }

  // After stop(): "N stalls >= T ms (one CPU while another ran: S, every CPU at once: B), longest L
  // ms".
  std::string summary(double threshold_ms) const {
    int alone = 0, together = 0;
    double longest_ms = 0.0;
    for (std::size_t cpu = 0; cpu < stalls_.size(); ++cpu) {
      for (const Stall& s : stalls_[cpu]) {
        longest_ms = std::max(longest_ms, s.late_ns * 1e-6);
        if (s.late_ns * 1e-6 < threshold_ms) continue;
        (held_everywhere(cpu, s) ? together : alone) += 1;
      }
    }
    char line[200];
    std::snprintf(line, sizeof line,
                  "%d stalls >= %.0f ms (one CPU while another ran: %d, every CPU at once: %d), "
                  "longest %.1f ms%s%s",
                  alone + together, threshold_ms, alone, together, longest_ms,
                  realtime_ ? "" : " (not SCHED_FIFO: also the guest's own load)",
                  pinned_ ? "" : " (not pinned: CPUs mixed up)");
    return line;
  }

 private:
  static std::int64_t now_ns() {
    timespec t{};
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec * 1'000'000'000LL + t.tv_nsec;
  }

  // Every other CPU also woke late, within 2 ms of this wake: the whole machine was held.
  bool held_everywhere(std::size_t cpu, const Stall& s) const {
    for (std::size_t other = 0; other < stalls_.size(); ++other) {
      if (other == cpu) continue;
      const bool also =
          std::any_of(stalls_[other].begin(), stalls_[other].end(), [&](const Stall& o) {
            return std::abs(o.woke_ns - s.woke_ns) < 2'000'000 && o.late_ns > 3'000'000;
          });
      if (!also) return false;
    }
    return stalls_.size() > 1;
  }

  void watch(std::size_t slot, int cpu) {
    cpu_set_t one;
    CPU_ZERO(&one);
    CPU_SET(cpu, &one);
    if (pthread_setaffinity_np(pthread_self(), sizeof one, &one) != 0) pinned_ = false;
    sched_param top{};
    top.sched_priority = 99;
    if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &top) != 0) realtime_ = false;
    std::vector<Stall>& mine = stalls_[slot];
    mine.reserve(1 << 16);
    std::int64_t deadline = now_ns();
    while (!stop_.load(std::memory_order_relaxed)) {
      deadline += 1'000'000;
      const timespec at{static_cast<time_t>(deadline / 1'000'000'000LL),
                        static_cast<long>(deadline % 1'000'000'000LL)};
      clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &at, nullptr);
      const std::int64_t woke = now_ns();
      if (woke - deadline > 5'000'000 && mine.size() < mine.capacity())
        mine.push_back({woke, woke - deadline});
      deadline = std::max(deadline, woke - 1'000'000);  // after a stall: on from now, no burst
    }
  }

  std::vector<std::vector<Stall>> stalls_;
  std::vector<std::thread> threads_;
  std::atomic<bool> stop_{false};
  std::atomic<bool> realtime_{true};
  std::atomic<bool> pinned_{true};
};

}  // namespace rig::testing
