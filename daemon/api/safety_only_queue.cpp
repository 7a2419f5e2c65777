#include "safety_only_queue.hpp"

#include "sessions.hpp"

namespace rig::api {

SafetyOnlyQueue::Place SafetyOnlyQueue::enter(const std::shared_ptr<HttpSession>& session) {
  while (waiting_.size() >= kWaiting) evict_oldest();
  waiting_.push_back(session);
  return std::prev(waiting_.end());
}

void SafetyOnlyQueue::leave(Place place) {
  waiting_.erase(place);
}

bool SafetyOnlyQueue::evict_oldest() {
  if (waiting_.empty()) return false;
  const std::shared_ptr<HttpSession> oldest = waiting_.front().lock();
  waiting_.pop_front();
  if (oldest) oldest->evict();  // forgets its place: it is no longer queued
  return true;
}

}  // namespace rig::api
