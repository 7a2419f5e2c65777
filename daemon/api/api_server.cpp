#include "api_server.hpp"

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "sessions.hpp"

namespace rig::api {

ApiServer::ApiServer(ApiContext& context, const std::string& bind, int port)
    : context_(&context),
      limits_(context.config->api.max_clients, context.config->api.max_clients_per_address),
      acceptor_(io_),
      router_(io_, context) {
  const boost::asio::ip::tcp::endpoint endpoint(boost::asio::ip::make_address(bind),
                                                static_cast<unsigned short>(port));
  acceptor_.open(endpoint.protocol());
  acceptor_.set_option(boost::asio::socket_base::reuse_address(true));
  acceptor_.bind(endpoint);
  acceptor_.listen();
  port_ = acceptor_.local_endpoint().port();
}

ApiServer::~ApiServer() {
  stop();
}

void ApiServer::start() {
  accept();
  thread_ = std::thread([this] {
    raise_priority();
    run_guarded();
  });
}

// On a loaded machine a thread of normal priority can wait hundreds of milliseconds for a
// CPU (seen in ApiSafety's export test with both cores busy). The I/O thread answers stop
// and e-stop, so it gets a larger share (nice -10: ~9x a normal thread's weight), still
// below the RT loop (SCHED_FIFO) and without starving anyone. Needs CAP_SYS_NICE, which
// rigd's unit grants; without it rigd says so and runs on at normal priority.
void ApiServer::raise_priority() {
  const auto thread_id = static_cast<id_t>(::syscall(SYS_gettid));
  if (::setpriority(PRIO_PROCESS, thread_id, kIoThreadNice) != 0) {
    spdlog::warn("api: the I/O thread keeps normal priority (nice {} refused: {})", kIoThreadNice,
                 std::strerror(errno));
  }
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
      spdlog::error(
          "api: a request handler failed with an unknown exception (the API keeps serving)");
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
    if (ec == boost::asio::error::operation_aborted || !acceptor_.is_open()) return;  // stopping
    if (ec) return accept_again_after(ec);
    admit(std::move(socket));
    accept();
  });
}

// A failed accept (EMFILE, ENFILE, ENOBUFS: no descriptor or memory left) leaves the
// connection in the backlog, and accepting again at once would spin the I/O thread. Close
// the oldest stop/e-stop-only connection still waiting for its request, to free a
// descriptor, and try again shortly.
void ApiServer::accept_again_after(const boost::system::error_code& error) {
  context_->counters.accept_failures.fetch_add(1);
  spdlog::warn("api: accepting a connection failed: {} (trying again in 10 ms)", error.message());
  safety_only_.evict_oldest();
  accept_retry_.expires_after(
      std::chrono::milliseconds(10));  // [ms] short against a 100 ms e-stop bound
  accept_retry_.async_wait([this](const boost::system::error_code& ec) {
    if (!ec && acceptor_.is_open()) accept();
  });
}

void ApiServer::admit(boost::asio::ip::tcp::socket&& socket) {
  boost::system::error_code ec;
  const auto peer = socket.remote_endpoint(ec);
  if (ec) return;  // already gone
  auto why = limits_.refusal(peer.address());
  if (!why) {
    std::make_shared<HttpSession>(std::move(socket), *this, limits_.take(peer.address()))->run();
    return;
  }
  // Refused a general slot, still read: stop and e-stop must get through whoever holds the
  // slots. The oldest such connection still waiting for its request makes room if need be.
  if (safety_only_.waiting() >= SafetyOnlyQueue::kWaiting) warn_of_eviction();
  std::make_shared<HttpSession>(std::move(socket), *this, std::move(*why))->run();
}

void ApiServer::warn_of_eviction() {
  const auto now = std::chrono::steady_clock::now();
  if (now - last_eviction_warning_ < std::chrono::seconds(1))
    return;  // at most one line a second in a flood
  last_eviction_warning_ = now;
  spdlog::warn(
      "api: {} connections wait for stop/e-stop only: closing the oldest for each new one ({} "
      "closed so far)",
      safety_only_.waiting(), context_->counters.connections_evicted.load());
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
