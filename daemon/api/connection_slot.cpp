#include "connection_slot.hpp"

#include "connection_limits.hpp"

namespace rig::api {

ConnectionSlot::~ConnectionSlot() {
  limits_->release(peer_);
}

}  // namespace rig::api
