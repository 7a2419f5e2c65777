#include "sessions.hpp"

#include "request_guard.hpp"

#include <spdlog/spdlog.h>

#include <chrono>

namespace rig::api {
namespace beast = boost::beast;
namespace websocket = beast::websocket;

HttpSession::HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server,
                         std::unique_ptr<ConnectionSlot> slot)
    : stream_(std::move(socket)), server_(&server), slot_(std::move(slot)), safety_only_(false) {
  server_->context().counters.open_connections.fetch_add(1);
}

HttpSession::HttpSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server, std::string why)
    : stream_(std::move(socket)),
      server_(&server),
      safety_only_(true),
      safety_only_reason_(std::move(why)) {
  server_->context().counters.open_connections.fetch_add(1);
  server_->context().counters.safety_only_connections.fetch_add(1);
}

HttpSession::~HttpSession() {
  leave_safety_only_queue();
  server_->context().counters.open_connections.fetch_sub(1);
  if (safety_only_) server_->context().counters.safety_only_connections.fetch_sub(1);
}

void HttpSession::run() {
  if (safety_only_) waiting_place_ = server_->safety_only_queue().enter(shared_from_this());
  read();
}

void HttpSession::evict() {
  waiting_place_.reset();
  server_->context().counters.connections_evicted.fetch_add(1);
  stream_.close();  // the pending read ends with operation_aborted, and with it the session
}

void HttpSession::leave_safety_only_queue() {
  if (!waiting_place_) return;
  server_->safety_only_queue().leave(*waiting_place_);
  waiting_place_.reset();
}

void HttpSession::read() {
  parser_.emplace();
  parser_->body_limit(static_cast<std::uint64_t>(server_->context().config->api.max_body_bytes));
  parser_->header_limit(16 * 1024);
  stream_.expires_after(safety_only_ ? kSafetyOnlyReadTimeout
                                     : kReadTimeout);  // a silent client is dropped
  http::async_read(
      stream_, buffer_, *parser_,
      [self = shared_from_this()](beast::error_code ec, std::size_t) { self->on_read(ec); });
}

void HttpSession::on_read(beast::error_code ec) {
  leave_safety_only_queue();  // read or failed: an answer being made is never evicted
  if (ec == http::error::end_of_stream || ec == beast::error::timeout) {
    stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
    return;
  }
  if (ec == http::error::body_limit) {
    Request empty;
    send(error_response(empty, http::status::payload_too_large,
                        "request body larger than api.max_body_bytes"));
    return;
  }
  if (ec) return;
  serve(parser_->release());
}

void HttpSession::serve(Request&& request) {
  if (safety_only_ && !is_safety_request(request)) {
    request.keep_alive(false);
    return send(error_response(request, http::status::service_unavailable, safety_only_reason_));
  }
  if (safety_only_) request.keep_alive(false);
  const std::string target(request.target());
  if (websocket::is_upgrade(request) && target.substr(0, target.find('?')) == "/ws")
    return upgrade(std::move(request));
  server_->router().handle(request, [self = shared_from_this()](Response&& response) {
    self->send(std::move(response));
  });
}

void HttpSession::upgrade(Request&& request) {
  if (const auto why = server_->context().guard.upgrade_refusal(request)) {
    server_->context().counters.refused_cross_site.fetch_add(1);
    spdlog::warn("api: refused a WebSocket upgrade: {}", *why);
    return send(error_response(request, http::status::forbidden, *why));
  }
  if (!server_->context().auth.authorized(request)) {
    server_->context().counters.refused_unauthorized.fetch_add(1);
    return send(
        error_response(request, http::status::unauthorized, "a valid API token is required"));
  }
  stream_.expires_never();
  std::make_shared<WsSession>(stream_.release_socket(), *server_, std::move(slot_))->run(request);
}

void HttpSession::send(Response&& response) {
  auto shared = std::make_shared<Response>(std::move(response));
  http::async_write(
      stream_, *shared, [self = shared_from_this(), shared](beast::error_code ec, std::size_t) {
        if (ec) return;
        if (!shared->keep_alive()) {
          self->stream_.socket().shutdown(boost::asio::ip::tcp::socket::shutdown_send, ec);
          return;
        }
        self->read();
      });
}

WsSession::WsSession(boost::asio::ip::tcp::socket&& socket, ApiServer& server,
                     std::unique_ptr<ConnectionSlot> slot)
    : ws_(std::move(socket)), server_(&server), slot_(std::move(slot)) {}

void WsSession::run(const Request& request) {
  // Bounded kernel buffer per client (~2 s of stream): a client that stops reading fills it
  // quickly, and then loses its own oldest messages in our queue, counted.
  boost::system::error_code ignored;
  beast::get_lowest_layer(ws_).socket().set_option(
      boost::asio::socket_base::send_buffer_size(256 * 1024), ignored);
  ws_.set_option(websocket::stream_base::timeout::suggested(beast::role_type::server));
  ws_.read_message_max(4096);  // clients only send pings
  ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) {
    if (ec) return;
    self->open_ = true;
    self->server_->add_stream_client(self);
    const double iop = self->server_->context().channels->status.read().params.iop_mmHg;
    self->send(
        std::make_shared<const std::string>(self->server_->context().hub->model_curve_json(iop)));
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
  ws_.async_write(boost::asio::buffer(*queue_.front()),
                  [self = shared_from_this()](beast::error_code ec, std::size_t) {
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
