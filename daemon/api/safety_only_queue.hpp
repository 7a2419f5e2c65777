#pragma once
// Connections refused a general slot (connection_limits.hpp) that are still waiting for their
// request, oldest first. They are read for stop and e-stop only, for at most
// HttpSession::kSafetyOnlyReadTimeout; at most kWaiting of them are kept, and a newer one
// evicts the oldest. So however many connections a client opens (idle, slow-loris, streams),
// a new connection is read at once and keeps its place for the next kWaiting connections to
// arrive, far longer than a client takes to send "POST /api/estop" after connecting.
// A connection whose request has been read has left the queue: an e-stop being answered is
// never evicted. I/O thread only.
#include <cstddef>
#include <list>
#include <memory>

namespace rig::api {

class HttpSession;

class SafetyOnlyQueue {
 public:
  // Waiting connections kept; each costs a descriptor and ~1 KiB of buffers.
  static constexpr std::size_t kWaiting = 64;
  using Place = std::list<std::weak_ptr<HttpSession>>::iterator;

  // Makes room for one more (evicting the oldest waiting connection if kWaiting wait
  // already), then queues `session`. Returns its place, for leave().
  Place enter(const std::shared_ptr<HttpSession>& session);
  void leave(Place place);
  // Closes the oldest waiting connection, if any (also to free a descriptor when accept
  // fails for want of one). Returns whether one was closed.
  bool evict_oldest();

  std::size_t waiting() const { return waiting_.size(); }

 private:
  std::list<std::weak_ptr<HttpSession>> waiting_;
};

}  // namespace rig::api
