#pragma once
// rigd's HTTP + WebSocket server (Boost.Beast) on one I/O thread. It is a stream sink:
// batches from the stream hub are posted to the I/O thread and queued per client with a
// bound, so a slow or hostile client only loses its own oldest messages.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>

#include <memory>
#include <set>
#include <thread>

#include "api_context.hpp"
#include "api_router.hpp"
#include "stream_sink.hpp"

namespace rig::api {

class WsSession;

class ApiServer final : public service::StreamSink {
 public:
  ApiServer(ApiContext& context, const std::string& bind, int port);  // binds; throws
  ~ApiServer() override;
  void start();
  void stop();
  // Connections beyond api.max_clients that are still read, for stop / e-stop only.
  static constexpr int kSafetyOnlyConnections = 64;
  int port() const { return port_; }

  void publish(std::shared_ptr<const std::string> message) override;

  // Used by the sessions (I/O thread only).
  ApiContext& context() { return *context_; }
  ApiRouter& router() { return router_; }
  boost::asio::io_context& io() { return io_; }
  void add_stream_client(const std::shared_ptr<WsSession>& session);
  void remove_stream_client(const std::shared_ptr<WsSession>& session);

 private:
  void accept();
  void run_guarded();

  ApiContext* context_;
  boost::asio::io_context io_;
  boost::asio::ip::tcp::acceptor acceptor_;
  ApiRouter router_;
  std::set<std::shared_ptr<WsSession>> stream_clients_;
  std::thread thread_;
  int port_ = 0;
};

}  // namespace rig::api
