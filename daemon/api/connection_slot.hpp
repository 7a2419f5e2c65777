#pragma once
// One general connection slot of a peer address (connection_limits.hpp), held by the HTTP
// session and handed on to its WebSocket session on upgrade; given back when destroyed.
#include <boost/asio/ip/address.hpp>

namespace rig::api {

class ConnectionLimits;

class ConnectionSlot {
 public:
  ConnectionSlot(ConnectionLimits& limits, boost::asio::ip::address peer)
      : limits_(&limits), peer_(std::move(peer)) {}
  ~ConnectionSlot();
  ConnectionSlot(const ConnectionSlot&) = delete;
  ConnectionSlot& operator=(const ConnectionSlot&) = delete;

  const boost::asio::ip::address& peer() const { return peer_; }

 private:
  ConnectionLimits* limits_;
  boost::asio::ip::address peer_;
};

}  // namespace rig::api
