#pragma once
// One HTTP request on a new connection from a chosen local address (127.0.0.2, ... are other
// clients to rigd on loopback), with a time limit: a server that never answers is a failed
// probe, not a hung test.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <chrono>
#include <optional>
#include <string>

namespace rig::testing {

struct ProbeReply {
  bool answered = false;  // a whole response arrived in time
  int status = 0;
  std::string body;
  std::string error;     // why not answered (connection closed, time-out, ...)
  double took_ms = 0.0;  // connect to the end of the response
  // Of that, the connect alone: on loopback the kernel completes the handshake without rigd
  // (its accept queue is not full), so this is the machine's and this client's scheduling.
  double connected_ms = 0.0;
};

inline ProbeReply http_probe(int port, boost::beast::http::verb method, const std::string& target,
                             const std::string& source = "127.0.0.1",
                             std::chrono::milliseconds limit = std::chrono::milliseconds(5000)) {
  namespace beast = boost::beast;
  namespace http = beast::http;
  using boost::asio::ip::tcp;
  boost::asio::io_context io;
  beast::tcp_stream stream(io);
  ProbeReply reply;
  http::request<http::string_body> request{method, target, 11};
  request.set(http::field::host, "127.0.0.1");
  if (method == http::verb::post) {
    request.set(http::field::content_type, "application/json");
    request.body() = "{}";
  }
  request.prepare_payload();
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  const auto start = std::chrono::steady_clock::now();
  stream.socket().open(tcp::v4());
  stream.socket().bind({boost::asio::ip::make_address(source), 0});
  stream.expires_after(limit);
  stream.async_connect(
      {boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)},
      [&](beast::error_code ec) {
        if (ec) return void(reply.error = "connect: " + ec.message());
        reply.connected_ms =
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
                .count();
        http::async_write(stream, request, [&](beast::error_code wec, std::size_t) {
          if (wec) return void(reply.error = "write: " + wec.message());
          http::async_read(stream, buffer, response, [&](beast::error_code rec, std::size_t) {
            if (rec) return void(reply.error = "read: " + rec.message());
            reply.answered = true;
          });
        });
      });
  io.run();
  reply.took_ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  if (reply.answered) {
    reply.status = static_cast<int>(response.result_int());
    reply.body = response.body();
  }
  return reply;
}

// The port of a URL like http://127.0.0.1:PORT.
inline int port_of(const std::string& url) {
  return std::stoi(url.substr(url.rfind(':') + 1));
}

}  // namespace rig::testing
