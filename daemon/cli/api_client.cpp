#include "api_client.hpp"

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>

#include <regex>

namespace rig::cli {
namespace beast = boost::beast;
namespace http = beast::http;

ApiClient::ApiClient(std::string url, std::string token)
    : url_(std::move(url)), token_(std::move(token)) {
  static const std::regex kUrl(R"(^http://([^/:]+|\[[0-9a-fA-F:]+\]):(\d+)/?$)");
  std::smatch m;
  if (!std::regex_match(url_, m, kUrl))
    throw ApiClientError("--api " + url_ + ": expected http://HOST:PORT");
  host_ = m[1].str();
  port_ = m[2].str();
}

HttpReply ApiClient::get(const std::string& path) const {
  return request(false, path, "");
}
HttpReply ApiClient::post(const std::string& path, const std::string& body) const {
  return request(true, path, body);
}

HttpReply ApiClient::request(bool post, const std::string& path, const std::string& body) const {
  try {
    boost::asio::io_context io;
    boost::asio::ip::tcp::resolver resolver(io);
    beast::tcp_stream stream(io);
    stream.expires_after(std::chrono::seconds(30));
    stream.connect(resolver.resolve(host_, port_));
    http::request<http::string_body> req{post ? http::verb::post : http::verb::get, path, 11};
    req.set(http::field::host, host_);
    req.set(http::field::user_agent, "rig-cli");
    if (!token_.empty()) req.set(http::field::authorization, "Bearer " + token_);
    if (post) {
      req.set(http::field::content_type, "application/json");
      req.body() = body;
      req.prepare_payload();
    }
    http::write(stream, req);
    beast::flat_buffer buffer;
    http::response_parser<http::string_body> parser;
    parser.body_limit(std::uint64_t{512} * 1024 * 1024);
    http::read(stream, buffer, parser);
    beast::error_code ignored;
    stream.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_both, ignored);
    return {static_cast<int>(parser.get().result_int()), parser.get().body()};
  } catch (const boost::system::system_error& e) {
    throw ApiClientError("cannot reach rigd at " + url_ + ": " + e.code().message() +
                         " (is rigd running? see --api)");
  }
}

}  // namespace rig::cli
