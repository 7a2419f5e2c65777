#pragma once
// TCP connections to rigd on loopback from a chosen local address (127.0.0.2, ... are other
// clients to rigd), and whether the server has closed one.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <cerrno>
#include <memory>
#include <string>

#include <sys/socket.h>

namespace rig::testing {

// A connected TCP socket from `source` to 127.0.0.1:port; throws if the connect fails.
inline std::unique_ptr<boost::asio::ip::tcp::socket> connect_from(boost::asio::io_context& io,
                                                                  const std::string& source,
                                                                  int port) {
  auto socket = std::make_unique<boost::asio::ip::tcp::socket>(io);
  socket->open(boost::asio::ip::tcp::v4());
  socket->bind({boost::asio::ip::make_address(source), 0});
  socket->connect({boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
  return socket;
}

// Whether the server has closed (FIN or RST) a connection we never read from; does not wait.
inline bool closed_by_server(boost::asio::ip::tcp::socket& socket) {
  char byte = 0;
  const ssize_t n = ::recv(socket.native_handle(), &byte, 1, MSG_PEEK | MSG_DONTWAIT);
  return n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK);
}

}  // namespace rig::testing
