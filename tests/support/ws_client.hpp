#pragma once
// A blocking WebSocket client on rigd's /ws, for end-to-end tests.
#include <nlohmann/json.hpp>

#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <regex>
#include <string>

namespace rig::testing {

struct WsClient {
  boost::asio::io_context io;
  boost::beast::websocket::stream<boost::beast::tcp_stream> ws{io};
  explicit WsClient(const std::string& url, int receive_buffer = 0) {
    std::smatch m;
    std::regex_search(url, m, std::regex(R"(http://([^:]+):(\d+))"));
    auto& socket = boost::beast::get_lowest_layer(ws).socket();
    socket.open(boost::asio::ip::tcp::v4());
    if (receive_buffer > 0)
      socket.set_option(boost::asio::socket_base::receive_buffer_size(receive_buffer));
    socket.connect({boost::asio::ip::make_address(m[1].str()),
                    static_cast<unsigned short>(std::stoi(m[2].str()))});
    ws.handshake(m[1].str(), "/ws");
  }
  nlohmann::json next() {
    boost::beast::flat_buffer buffer;
    ws.read(buffer);
    return nlohmann::json::parse(boost::beast::buffers_to_string(buffer.data()));
  }
};

}  // namespace rig::testing
