#include "commit_cadence.hpp"

#include <algorithm>

namespace rig::service {

CommitCadence::Clock::time_point CommitCadence::after_commit(Clock::time_point due, Clock::time_point began,
                                                             Clock::time_point ended) {
  const Clock::duration late = std::max(Clock::duration::zero(), began - due);
  costs_[next_] = (ended - began) + late;
  next_ = (next_ + 1) % kRecent;
  return std::max(ended, after_empty_check(began));
}

CommitCadence::Clock::time_point CommitCadence::after_empty_check(Clock::time_point began) const {
  return began + interval_ - drain_period_ - recent_cost();
}

CommitCadence::Clock::duration CommitCadence::recent_cost() const { return *std::max_element(costs_.begin(), costs_.end()); }

}  // namespace rig::service
