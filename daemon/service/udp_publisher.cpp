#include "udp_publisher.hpp"

#include <nlohmann/json.hpp>

namespace rig::service {

UdpPublisher::UdpPublisher(const std::string& host, int port)
    : socket_(io_),
      destination_(boost::asio::ip::make_address(host), static_cast<unsigned short>(port)) {
  socket_.open(destination_.protocol());
  socket_.non_blocking(true);  // a full socket buffer drops the datagram instead of waiting
}

void UdpPublisher::publish(std::shared_ptr<const std::string> message) {
  // Only sample batches go out; add the explicit timestamp PlotJuggler asks for.
  nlohmann::json j = nlohmann::json::parse(*message, nullptr, false);
  if (!j.is_object() || j.value("type", "") != "samples" || j["t_s"].empty()) return;
  j["timestamp"] = j["t_s"].back();
  const std::string datagram = j.dump();
  if (datagram.size() > 60000) return;  // larger than a datagram: shorten stream.batch_ms
  boost::system::error_code error;
  socket_.send_to(boost::asio::buffer(datagram), destination_, 0, error);
  (error ? failed_ : sent_).fetch_add(1);
}

}  // namespace rig::service
