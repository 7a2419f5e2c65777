#pragma once
// One HTTP connection (keep-alive, size-limited bodies, read time-out) and one WebSocket
// stream client (bounded send queue).
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <chrono>
#include <deque>
#include <memory>
#include <optional>
#include <string>

#include "api_server.hpp"
#include "connection_slot.hpp"
#include "http_types.hpp"
#include "safety_only_queue.hpp"

namespace rig::api {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // A silent or slow client (slow-loris) is dropped after this long per request: the time
  // limit covers the whole request, however the bytes trickle in.
  static constexpr std::chrono::seconds kReadTimeout{15};
  // A connection refused a general slot gets this long to send its request (a client sends
  // "POST /api/estop" within milliseconds of connecting); it may be evicted sooner
  // (safety_only_queue.hpp).
  static constexpr std::chrono::seconds kSafetyOnlyReadTimeout{2};

  // A general connection, holding `slot` (connection_limits.hpp).
  HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server,
              std::unique_ptr<ConnectionSlot> slot);
  // A connection refused a general slot for `why`: served stop / e-stop only, queued for
  // eviction until its request is read, and closed after one answer.
  HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server, std::string why);
  ~HttpSession();
  void run();
  // Closes a safety-only connection still waiting for its request, without an answer
  // (SafetyOnlyQueue: it has already forgotten the connection's place).
  void evict();

 private:
  void read();
  void on_read(boost::beast::error_code ec);
  void serve(Request&& request);
  void upgrade(Request&& request);
  void send(Response&& response);
  void leave_safety_only_queue();

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  ApiServer* server_;
  std::unique_ptr<ConnectionSlot> slot_;  // general connections; handed to a WebSocket session
  const bool safety_only_;
  std::string safety_only_reason_;                       // the 503's text for any other request
  std::optional<SafetyOnlyQueue::Place> waiting_place_;  // while safety-only and unread
};

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  static constexpr std::size_t kMaxQueuedMessages = 64;  // ~3 s of 50 ms batches

  // slot: the general connection slot of the HTTP session it was upgraded from.
  WsSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server,
            std::unique_ptr<ConnectionSlot> slot);
  void run(const Request& request);
  void send(std::shared_ptr<const std::string> message);  // I/O thread

 private:
  void write_next();
  void read();
  void close();

  boost::beast::websocket::stream<boost::beast::tcp_stream> ws_;
  boost::beast::flat_buffer buffer_;
  std::deque<std::shared_ptr<const std::string>> queue_;
  bool writing_ = false;
  bool open_ = false;
  ApiServer* server_;
  std::unique_ptr<ConnectionSlot> slot_;  // given back when the stream's last handler ends
};

}  // namespace rig::api
