#pragma once
// One HTTP connection (keep-alive, size-limited bodies, read time-out) and one WebSocket
// stream client (bounded send queue).
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include <deque>
#include <memory>
#include <optional>

#include "api_server.hpp"
#include "http_types.hpp"

namespace rig::api {

class HttpSession : public std::enable_shared_from_this<HttpSession> {
 public:
  // safety_only: a connection beyond api.max_clients, served stop / e-stop only, read
  // with a short time-out and closed after one answer.
  HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server, bool safety_only);
  ~HttpSession();
  void run();

 private:
  void read();
  void on_read(boost::beast::error_code ec);
  void send(Response&& response);

  boost::beast::tcp_stream stream_;
  boost::beast::flat_buffer buffer_;
  std::optional<http::request_parser<http::string_body>> parser_;
  ApiServer* server_;
  bool safety_only_;
};

class WsSession : public std::enable_shared_from_this<WsSession> {
 public:
  static constexpr std::size_t kMaxQueuedMessages = 64;  // ~3 s of 50 ms batches

  WsSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server);
  void run(Request request);
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
};

}  // namespace rig::api
