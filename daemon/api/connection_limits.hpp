#pragma once
// Who may have a general connection: at most api.max_clients in all and
// api.max_clients_per_address from one peer address, HTTP and WebSocket alike. A connection
// refused a general slot is not closed: it is served stop and e-stop only (api_server.hpp),
// so no client, however many connections it opens, can lock out making the rig safe.
// I/O thread only.
#include <boost/asio/ip/address.hpp>

#include <map>
#include <memory>
#include <optional>
#include <string>

namespace rig::api {

class ConnectionSlot;

class ConnectionLimits {
 public:
  // max_per_address is capped at max_clients (a larger value means "no per-address cap").
  ConnectionLimits(int max_clients, int max_per_address);

  // Why `peer` cannot have a general connection now, or nothing.
  std::optional<std::string> refusal(const boost::asio::ip::address& peer) const;
  // A general slot for `peer`, given back when the slot is destroyed.
  std::unique_ptr<ConnectionSlot> take(const boost::asio::ip::address& peer);
  void release(const boost::asio::ip::address& peer);  // by ConnectionSlot only

  int in_use() const { return in_use_; }
  int held_by(const boost::asio::ip::address& peer) const;

 private:
  int max_clients_;
  int max_per_address_;
  int in_use_ = 0;
  std::map<boost::asio::ip::address, int> per_address_;  // addresses holding >= 1 slot
};

}  // namespace rig::api
