#include "api_server.hpp"

#include <boost/asio/post.hpp>
#include <spdlog/spdlog.h>

#include "sessions.hpp"

namespace rig::api {

ApiServer::ApiServer(ApiContext& context, const std::string& bind, int port)
    : context_(&context), acceptor_(io_), router_(io_, context) {
  const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(bind), static_cast<unsigned short>(port));
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen();
  port_ = acceptor_.local_endpoint().port();
}

ApiServer::~ApiServer() { stop(); }

void ApiServer::start() {
  accept();
  thread_ = std::thread([this] { run_guarded(); });
}

// A handler that throws must not take rigd (and with it the RT loop's supervisor) down:
// log it, count it, and keep serving. io_context::run rethrows a handler's exception and
// can be called again after it.
void ApiServer::run_guarded() {
  for (;;) {
    try {
      io_.run();
      return;  // stopped
    } catch (const std::exception& e) {
      context_->counters.handler_exceptions.fetch_add(1);
      spdlog::error("api: a request handler failed: {} (the API keeps serving)", e.what());
    } catch (...) {
      context_->counters.handler_exceptions.fetch_add(1);
      spdlog::error("api: a request handler failed with an unknown exception (the API keeps serving)");
    }
  }
}

void ApiServer::stop() {
  if (!thread_.joinable()) return;
  io_.stop();
  thread_.join();
}

void ApiServer::accept() {
  acceptor_.async_accept([this](boost::system::error_code ec, boost::asio::ip::tcp::socket socket) {
    if (!ec) {
      const auto& n = context_->counters;
      const bool full = n.open_connections.load() - n.safety_only_connections.load() + n.ws_clients.load() >= context_->config->api.max_clients;
      if (!full) {
        std::make_shared<HttpSession>(std::move(socket), *this, false)->run();
      } else if (n.safety_only_connections.load() < kSafetyOnlyConnections) {
        // At the limit a connection still gets in, to be served stop / e-stop only: idle or
        // streaming clients can never lock out making the rig safe.
        std::make_shared<HttpSession>(std::move(socket), *this, true)->run();
      } else {
        spdlog::warn("api: connection refused, {} clients already", n.open_connections.load());
        socket.close();
      }
    }
    if (acceptor_.is_open()) accept();
  });
}

void ApiServer::publish(std::shared_ptr<const std::string> message) {
  boost::asio::post(io_, [this, message = std::move(message)] {
    const auto clients = stream_clients_;  // a send may end a session
    for (const auto& client : clients) client->send(message);
  });
}

void ApiServer::add_stream_client(const std::shared_ptr<WsSession>& session) {
  stream_clients_.insert(session);
  context_->counters.ws_clients.store(static_cast<std::int64_t>(stream_clients_.size()));
}

void ApiServer::remove_stream_client(const std::shared_ptr<WsSession>& session) {
  stream_clients_.erase(session);
  context_->counters.ws_clients.store(static_cast<std::int64_t>(stream_clients_.size()));
}

}  // namespace rig::api
