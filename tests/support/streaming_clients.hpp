#pragma once
// WebSocket clients of rigd's /ws for the safety tests, from a chosen loopback address.
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "loopback_connect.hpp"

namespace rig::testing {

// WebSocket streams on /ws from `source`: `reading` ones read every message on a thread of
// their own (async, stopped in the destructor); the others never read (a stuck page).
class StreamingClients {
 public:
  StreamingClients(int port, const std::string& source, int reading, int stuck) {
    for (int i = 0; i < reading + stuck; ++i) {
      auto client = std::make_unique<Client>(io_);
      boost::beast::get_lowest_layer(client->ws).socket() =
          std::move(*connect_from(io_, source, port));
      client->ws.handshake("127.0.0.1", "/ws");
      clients_.push_back(std::move(client));
      if (i < reading) read_forever(*clients_.back());
    }
    reader_ = std::thread([this] { io_.run(); });
  }
  ~StreamingClients() {
    io_.stop();
    reader_.join();
  }
  std::uint64_t messages_read() const { return messages_read_.load(); }

 private:
  struct Client {
    explicit Client(boost::asio::io_context& io) : ws(io) {}
    boost::beast::websocket::stream<boost::beast::tcp_stream> ws;
    boost::beast::flat_buffer buffer;
  };
  void read_forever(Client& client) {
    client.ws.async_read(client.buffer, [this, &client](boost::beast::error_code ec, std::size_t) {
      if (ec) return;
      messages_read_.fetch_add(1);
      client.buffer.clear();
      read_forever(client);
    });
  }

  boost::asio::io_context io_;
  std::vector<std::unique_ptr<Client>> clients_;
  std::atomic<std::uint64_t> messages_read_{0};
  std::thread reader_;
};

}  // namespace rig::testing
