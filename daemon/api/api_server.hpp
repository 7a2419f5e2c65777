#pragma once
// rigd's HTTP + WebSocket server (Boost.Beast) on one I/O thread. It is a stream sink:
// batches from the stream hub are posted to the I/O thread and queued per client with a
// bound, so a slow or hostile client only loses its own oldest messages.
//
// Connections: a new one gets a general slot if api.max_clients and
// api.max_clients_per_address allow (connection_limits.hpp); otherwise it is still accepted
// and read, briefly, for stop and e-stop only (safety_only_queue.hpp evicts the oldest such
// connections first). So stop and e-stop get through whatever number of connections is
// open, idle, half-sent or streaming.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <memory>
#include <set>
#include <thread>

#include "api_context.hpp"
#include "api_router.hpp"
#include "connection_limits.hpp"
#include "safety_only_queue.hpp"
#include "stream_sink.hpp"

namespace rig::api {

class WsSession;

class ApiServer final : public service::StreamSink {
 public:
  ApiServer(ApiContext& context, const std::string& bind, int port);  // binds; throws
  ~ApiServer() override;
  void start();
  void stop();
  int port() const { return port_; }
  // Nice value of the I/O thread (normal: 0): it answers stop and e-stop first on a busy CPU.
  static constexpr int kIoThreadNice = -10;

  void publish(std::shared_ptr<const std::string> message) override;

  // Used by the sessions (I/O thread only).
  ApiContext& context() { return *context_; }
  ApiRouter& router() { return router_; }
  boost::asio::io_context& io() { return io_; }
  SafetyOnlyQueue& safety_only_queue() { return safety_only_; }
  void add_stream_client(const std::shared_ptr<WsSession>& session);
  void remove_stream_client(const std::shared_ptr<WsSession>& session);

 private:
  void accept();
  void accept_again_after(const boost::system::error_code& error);
  void admit(boost::asio::ip::tcp::socket&& socket);
  void warn_of_eviction();
  void run_guarded();
  void raise_priority();

  ApiContext* context_;
  // Before io_: sessions still queued in io_ when it is destroyed give their slots back here.
  ConnectionLimits limits_;
  SafetyOnlyQueue safety_only_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  boost::asio::steady_timer accept_retry_{io_};  // after a failed accept (no descriptor left)
  std::chrono::steady_clock::time_point last_eviction_warning_{};
  ApiRouter router_;
  std::set<std::shared_ptr<WsSession>> stream_clients_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace rig::api
