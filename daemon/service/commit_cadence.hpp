#pragma once
// When the recorder's next commit is due. A run's samples are durable once the commit after
// them has synced (wal_syncer.hpp: written by the recorder, synced by the syncer), so what a
// power cut can take (the exposure) runs from one commit's start to the end of the sync that
// made the next one durable: exposure = the gap between their starts + the second commit's
// cost to durable. To keep it within the flush interval, the next commit starts early by what
// the recent commits cost (write + sync, plus how late they began, the largest of the last
// kRecent) and by the drain period (a sample waits that long in the loop's ring). A slow
// disk or a starved recorder then means more frequent commits, not a longer exposure.
// Pure: the recorder passes its clock's times in (tests pass their own).
#include <array>
#include <chrono>
#include <cstddef>

namespace rig::service {

class CommitCadence {
 public:
  using Clock = std::chrono::steady_clock;
  // Costs remembered for the margin: two per commit (its write at after_commit, write + sync
  // at note_durable), so 64 are the last 32 commits (~1.3 s at 50 ms). With 8 commits
  // (~0.35 s) a lateness spike after a quiet spell went past the margin, and exposures of
  // 53-58 ms were common in the power-cut VM (2026-11-28: a cut lost 46-51 ms against 50 + 1).
  static constexpr std::size_t kRecent = 64;

  // Until kRecent costs are measured, a commit is assumed to cost half the interval: a fresh
  // rigd's margin was 0, so its first commits of samples overshot the interval by their whole
  // cost (a boot's longest exposure in the power-cut VM was ~60 ms at the median of boots,
  // 2026-12-02). At 50 ms that means a commit every ~23 ms for the first ~1 s.
  CommitCadence(Clock::duration flush_interval, Clock::duration drain_period)
      : interval_(flush_interval), drain_period_(drain_period) {
    costs_.fill(flush_interval / 2);
  }

  // A commit that was due at `due`, began at `began` and ended at `ended`; returns when the
  // next one is due: never before `ended`.
  Clock::time_point after_commit(Clock::time_point due, Clock::time_point began,
                                 Clock::time_point ended);
  // A commit became durable `cost` after it was due (lateness + write + sync): remembered
  // for the margin like a commit's own cost.
  void note_durable(Clock::duration cost);
  // A due time at `began` that found nothing to commit: when the next one is due.
  Clock::time_point after_empty_check(Clock::time_point began) const;
  // The current margin: the largest recent cost (duration + lateness).
  Clock::duration recent_cost() const;

 private:
  Clock::duration interval_;
  Clock::duration drain_period_;
  std::array<Clock::duration, kRecent> costs_{};
  std::size_t next_ = 0;
};

}  // namespace rig::service
