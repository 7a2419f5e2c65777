#include "commit_cadence.hpp"

#include <algorithm>

namespace rig::service {

CommitCadence::Clock::time_point CommitCadence::after_commit(Clock::time_point due,
                                                             Clock::time_point began,
                                                             Clock::time_point ended) {
  const Clock::duration late = std::max(Clock::duration::zero(), began - due);
  costs_[next_] = (ended - began) + late;
  next_ = (next_ + 1) % kRecent;
  return std::max(ended, after_empty_check(began));
}

void CommitCadence::note_durable(Clock::duration cost) {
  costs_[next_] = cost;
  next_ = (next_ + 1) % kRecent;
}

CommitCadence::Clock::time_point CommitCadence::after_empty_check(Clock::time_point began) const {
  // A margin above half the interval keeps no bound (the disk is slower than the interval):
  // commits then come every half interval, not back to back, so a stalled sync is not
  // answered with a write every drain period.
  return began + interval_ - drain_period_ - std::min(recent_cost(), interval_ / 2);
}

CommitCadence::Clock::duration CommitCadence::recent_cost() const {
  return *std::max_element(costs_.begin(), costs_.end());
}

}  // namespace rig::service
