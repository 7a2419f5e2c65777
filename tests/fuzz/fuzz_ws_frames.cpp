// libFuzzer target: the WebSocket frames a stream client sends to rigd after the upgrade,
// read by a server-role Beast stream with rigd's settings (read_message_max 4096, the
// suggested server time-outs) while the server writes the model curve as rigd does. The
// bytes are what the client sends after its handshake. A finding is a memory error, UB,
// an exception, a message read longer than the limit, or a stream that never ends.
#include <boost/asio/io_context.hpp>
#include <boost/beast/_experimental/test/stream.hpp>
#include <boost/beast/core/flat_buffer.hpp>
#include <boost/beast/websocket.hpp>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "fuzz_support.hpp"

namespace {

namespace beast = boost::beast;
namespace websocket = beast::websocket;

constexpr std::size_t kMaxMessage = 4096;  // sessions.cpp: clients only send pings

rig::fuzz::Request upgrade_request() {
  rig::fuzz::Request request{beast::http::verb::get, "/ws", 11};
  request.set(beast::http::field::host, "127.0.0.1:8080");
  request.set(beast::http::field::upgrade, "websocket");
  request.set(beast::http::field::connection, "Upgrade");
  request.set(beast::http::field::sec_websocket_key, "dGhlIHNhbXBsZSBub25jZQ==");
  request.set(beast::http::field::sec_websocket_version, "13");
  return request;
}

struct Session {
  Session(boost::asio::io_context& context, beast::test::stream&& socket)
      : io(&context), ws(std::move(socket)) {}
  void read() {
    ws.async_read(buffer, [this](beast::error_code ec, std::size_t n) {
      if (ec) return end();
      if (n > kMaxMessage || buffer.size() > kMaxMessage)
        rig::fuzz::fail("a message longer than read_message_max", std::to_string(n));
      buffer.consume(buffer.size());
      ++messages;
      read();
    });
  }
  void end() {
    ended = true;
    io->stop();  // the time-out timers would keep the context busy
  }
  boost::asio::io_context* io;
  websocket::stream<beast::test::stream> ws;
  beast::flat_buffer buffer;
  int messages = 0;
  bool ended = false;
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  boost::asio::io_context io;
  beast::test::stream server(io);
  beast::test::stream client = beast::test::connect(server);
  Session session(io, std::move(server));
  session.ws.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  session.ws.read_message_max(kMaxMessage);
  const std::string curve(600, 'm');
  const rig::fuzz::Request upgrade = upgrade_request();
  session.ws.async_accept(upgrade, [&](beast::error_code ec) {
    if (ec) return session.end();
    session.ws.text(true);
    session.ws.async_write(boost::asio::buffer(curve), [](beast::error_code, std::size_t) {});
    session.read();
  });
  session.ws.next_layer().append(beast::string_view(reinterpret_cast<const char*>(data), size));
  session.ws.next_layer().close_remote();  // the client sends nothing more: EOF after its bytes
  const std::size_t handlers = io.run_for(std::chrono::seconds(5));
  if (!session.ended)
    rig::fuzz::fail("the stream did not end within 5 s", std::to_string(handlers));
  return 0;
}
