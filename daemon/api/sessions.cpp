#include "sessions.hpp"

#include "request_guard.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

namespace rig::api {
namespace beast = boost::beast;
namespace websocket = beast::websocket;

HttpSession::HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server, bool safety_only)
    : stream_(std::move(socket)), server_(&server), safety_only_(safety_only) {
  server_->context().counters.open_connections.fetch_add(1);
  if (safety_only_) server_->context().counters.safety_only_connections.fetch_add(1);
}

HttpSession::~HttpSession() {
  server_->context().counters.open_connections.fetch_sub(1);
  if (safety_only_) server_->context().counters.safety_only_connections.fetch_sub(1);
}

void HttpSession::run() { read(); }

void HttpSession::read() {
  parser_.emplace();
  parser_->body_limit(static_cast<std::uint64_t>(server_->context().config->api.max_body_bytes));
  parser_->header_limit(16 * 1024);
  stream_.expires_after(std::chrono::seconds(safety_only_ ? 2 : 15));  // a silent client is dropped
  http::async_read(stream_, buffer_, *parser_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
  if (ec == http::error::end_of_stream || ec == beast::error::timeout) {
    stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
    return;
  }
  if (ec == http::error::body_limit) {
    Request empty;
    send(error_response(empty, http::status::payload_too_large, "request body larger than api.max_body_bytes"));
    return;
  }
  if (ec) return;
  Request request = parser_->release();
  if (safety_only_ && !is_safety_request(request)) {
    request.keep_alive(false);
    return send(error_response(request, http::status::service_unavailable,
                               "rigd is serving api.max_clients connections: only stop and e-stop are answered now"));
  }
  if (safety_only_) request.keep_alive(false);
  const std::string target(request.target());
  if (websocket::is_upgrade(request) && target.substr(0, target.find('?')) == "/ws") {
    if (const auto why = server_->context().guard.upgrade_refusal(request)) {
      server_->context().counters.refused_cross_site.fetch_add(1);
      spdlog::warn("api: refused a WebSocket upgrade: {}", *why);
      return send(error_response(request, http::status::forbidden, *why));
    }
    if (!server_->context().auth.authorized(request)) {
      server_->context().counters.refused_unauthorized.fetch_add(1);
      return send(error_response(request, http::status::unauthorized, "a valid API token is required"));
    }
    stream_.expires_never();
    std::make_shared<WsSession>(stream_.release_socket(), *server_)->run(std::move(request));
    return;
  }
  server_->router().handle(request, [self = shared_from_this()](Response&& response) { self->send(std::move(response)); });
}

void HttpSession::send(Response&& response) {
  auto shared = std::make_shared<Response>(std::move(response));
  http::async_write(stream_, *shared, [self = shared_from_this(), shared](beast::error_code ec, std::size_t) {
    if (ec) return;
    if (!shared->keep_alive()) {
      self->stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
      return;
    }
    self->read();
  });
}

WsSession::WsSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server)
    : ws_(std::move(socket)), server_(&server) {}

void WsSession::run(Request request) {
  // Bounded kernel buffer per client (~2 s of stream): a client that stops reading fills it
  // quickly, and then loses its own oldest messages in our queue, counted.
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().set_option(boost::asio::socket_base::send_buffer_size(256 * 1024), ignored);
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(4096);  // clients only send pings
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    self->open_ = true;
    self->server_->add_stream_client(self);
    const double iop = self->server_->context().channels->status.read().params.iop_mmHg;
    self->send(std::make_shared<const std::string>(self->server_->context().hub->model_curve_json(iop)));
    self->read();
  });
}

void WsSession::send(std::shared_ptr<const std::string> message) {
  if (!open_) return;
  if (queue_.size() >= kMaxQueuedMessages) {
    queue_.erase(queue_.begin() + (writing_ ? 1 : 0));  // never the one being written
    server_->context().counters.ws_messages_dropped.fetch_add(1);
  }
  queue_.push_back(std::move(message));
  if (!writing_) write_next();
}

void WsSession::write_next() {
  if (queue_.empty() || !open_) {
    writing_ = false;
    return;
  }
  writing_ = true;
  ws_.text(true);
  ws_.async_write(boost::asio::buffer(*queue_.front()), [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) return self->close();
    self->server_->context().counters.ws_messages_sent.fetch_add(1);
    self->queue_.pop_front();
    self->write_next();
  });
}

void WsSession::read() {
  ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) {
    if (ec) return self->close();
    self->buffer_.consume(self->buffer_.size());
    self->read();
  });
}

void WsSession::close() {
  if (!open_) return;
  open_ = false;
  queue_.clear();
  server_->remove_stream_client(shared_from_this());
}

}  // namespace rig::api
