#pragma once
// PlotJuggler / any-tool live stream: the same batches as the WebSocket, as JSON datagrams
// over UDP. Every datagram has an explicit "timestamp" (loop time of its last sample [s]),
// which PlotJuggler's UDP plugin uses as the time field; per-sample times are in t_s.
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>

#include <atomic>
#include <string>

#include "stream_sink.hpp"

namespace rig::service {

class UdpPublisher final : public StreamSink {
 public:
  UdpPublisher(const std::string& host, int port);
  void publish(std::shared_ptr<const std::string> message) override;
  std::uint64_t sent() const { return sent_.load(); }
  std::uint64_t failed() const { return failed_.load(); }

 private:
  boost::asio::io_context io_;
  boost::asio::ip::udp::socket socket_;
  boost::asio::ip::udp::endpoint destination_;
  std::atomic<std::uint64_t> sent_{0};
  std::atomic<std::uint64_t> failed_{0};
};

}  // namespace rig::service
