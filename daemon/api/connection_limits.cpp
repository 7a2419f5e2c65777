#include "connection_limits.hpp"

#include <algorithm>

#include "connection_slot.hpp"

namespace rig::api {

ConnectionLimits::ConnectionLimits(int max_clients, int max_per_address)
    : max_clients_(max_clients), max_per_address_(std::min(max_per_address, max_clients)) {}

int ConnectionLimits::held_by(const boost::asio::ip::address& peer) const {
  const auto it = per_address_.find(peer);
  return it == per_address_.end() ? 0 : it->second;
}

std::optional<std::string> ConnectionLimits::refusal(const boost::asio::ip::address& peer) const {
  if (in_use_ >= max_clients_) {
    return "rigd is serving api.max_clients (" + std::to_string(max_clients_) +
           ") connections: only stop and e-stop are answered now";
  }
  if (held_by(peer) >= max_per_address_) {
    return "this address already holds api.max_clients_per_address (" +
           std::to_string(max_per_address_) +
           ") connections: only stop and e-stop are answered on another one";
  }
  return std::nullopt;
}

std::unique_ptr<ConnectionSlot> ConnectionLimits::take(const boost::asio::ip::address& peer) {
  ++in_use_;
  ++per_address_[peer];
  return std::make_unique<ConnectionSlot>(*this, peer);
}

void ConnectionLimits::release(const boost::asio::ip::address& peer) {
  --in_use_;
  const auto it = per_address_.find(peer);
  if (it != per_address_.end() && --it->second <= 0) per_address_.erase(it);
}

}  // namespace rig::api
