// rigd's API server in-process on loopback (real sockets, no RT loop): an exception thrown
// from a request handler, a posted handler or a timer is counted and the server keeps
// answering; one address cannot take more than api.max_clients_per_address connections, and
// connections refused a slot are served stop / e-stop only, the oldest evicted first.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <stdexcept>
#include <thread>

#include "api_server.hpp"
#include "http_probe.hpp"
#include "silent_clients.hpp"
#include "stream_hub.hpp"
#include "test_paths.hpp"

namespace rig::api {
namespace {

using boost::beast::http::verb;

class ApiServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spdlog::set_level(spdlog::level::off);
    config_.archive.path = dir_.file("archive.sqlite");
    config_.api.web_root = dir_.path().string();
    context_.channels = &channels_;
    context_.hub = &hub_;
    context_.config = &config_;
  }
  void TearDown() override {
    server_.reset();
    spdlog::set_level(spdlog::level::info);
  }
  void start(int max_clients, int max_clients_per_address) {
    config_.api.max_clients = max_clients;
    config_.api.max_clients_per_address = max_clients_per_address;
    server_ = std::make_unique<ApiServer>(context_, "127.0.0.1", 0);
    server_->start();
  }
  testing::ProbeReply get(const std::string& target, const std::string& source = "127.0.0.1") {
    return testing::http_probe(server_->port(), verb::get, target, source);
  }
  // Waits up to 5 s for `done` (the server's I/O thread works on its own time).
  static bool eventually(const std::function<bool()>& done) {
    for (int i = 0; i < 500; ++i) {
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    return done();
  }

  testing::ScratchDir dir_{"api-server"};
  rt::LoopChannels channels_{1024};
  service::StreamHub hub_{channels_, 20.0, 50};
  config::RigdConfig config_;
  ApiContext context_;
  std::unique_ptr<ApiServer> server_;
};

TEST_F(
    ApiServerTest,
    ExceptionsThrownFromARequestHandlerAPostedHandlerAndATimerAreCountedAndTheServerKeepsAnswering) {
  std::atomic<bool> thrown{false};
  // A fault past the router's own error handling (it catches std::exception only): the
  // Prometheus hook of a driver throwing something that is not a std::exception.
  context_.extra_metrics = [&thrown]() -> std::string {
    if (!thrown.exchange(true)) throw 42;
    return "";
  };
  start(16, 16);
  const testing::ProbeReply first = get("/metrics");
  EXPECT_FALSE(first.answered) << "the throwing request's connection ends unanswered: "
                               << first.body;
  ASSERT_TRUE(eventually([&] { return context_.counters.handler_exceptions.load() == 1; }))
      << context_.counters.handler_exceptions.load();

  boost::asio::post(server_->io(), [] { throw std::runtime_error("a posted handler failed"); });
  auto timer =
      std::make_shared<boost::asio::steady_timer>(server_->io(), std::chrono::milliseconds(20));
  timer->async_wait([timer](const boost::system::error_code&) {
    throw std::logic_error("a timer's handler failed");
  });
  ASSERT_TRUE(eventually([&] { return context_.counters.handler_exceptions.load() == 3; }))
      << context_.counters.handler_exceptions.load();

  const testing::ProbeReply status = get("/api/status");
  EXPECT_EQ(status.status, 200) << status.error << status.body;
  const testing::ProbeReply metrics = get("/metrics");
  EXPECT_EQ(metrics.status, 200) << metrics.error << metrics.body;
  EXPECT_NE(metrics.body.find("rigd_api_handler_exceptions_total 3\n"), std::string::npos)
      << metrics.body;
}

TEST_F(ApiServerTest,
       AnAddressHoldingItsShareOfConnectionsIsServedStopOnlyOnAnotherWhileOtherAddressesAreServed) {
  start(8, 2);
  testing::SilentClients idle(server_->port());
  idle.open_idle("127.0.0.2", 2);
  ASSERT_TRUE(eventually([&] { return context_.counters.open_connections.load() == 2; }));

  const testing::ProbeReply refused = get("/api/status", "127.0.0.2");
  EXPECT_EQ(refused.status, 503) << refused.error << refused.body;
  EXPECT_NE(refused.body.find("api.max_clients_per_address (2)"), std::string::npos)
      << refused.body;
  EXPECT_NE(refused.body.find("only stop and e-stop"), std::string::npos) << refused.body;
  const testing::ProbeReply other = get("/api/status", "127.0.0.3");
  EXPECT_EQ(other.status, 200) << other.error << other.body;
  // Stopping reaches the router from the capped address (no haptic device here: it says so).
  const testing::ProbeReply stop =
      testing::http_probe(server_->port(), verb::post, "/api/haptic/stop", "127.0.0.2");
  EXPECT_NE(stop.body.find("haptic playback is not available"), std::string::npos)
      << stop.error << stop.body;

  idle.close_oldest();  // one slot of 127.0.0.2 comes free
  EXPECT_TRUE(eventually([&] { return get("/api/status", "127.0.0.2").status == 200; }));
}

TEST_F(ApiServerTest, ConnectionsRefusedASlotAreEvictedOldestFirstSoANewOneIsAlwaysRead) {
  start(1, 1);
  testing::SilentClients idle(server_->port());
  idle.open_idle("127.0.0.1", 1);  // takes the only general slot
  const int beyond = static_cast<int>(SafetyOnlyQueue::kWaiting) + 20;
  idle.open_idle("127.0.0.1", beyond);
  ASSERT_TRUE(eventually([&] { return context_.counters.connections_evicted.load() == 20; }))
      << context_.counters.connections_evicted.load();
  EXPECT_TRUE(eventually([&] { return idle.closed_by_server_count(21) == 20; }))
      << "the 20 oldest refused ones are closed";
  EXPECT_EQ(idle.closed_by_server_count(), 20)
      << "the general one and the newest refused ones are kept";
  EXPECT_TRUE(eventually([&] {
    return context_.counters.safety_only_connections.load() ==
           static_cast<std::int64_t>(SafetyOnlyQueue::kWaiting);
  })) << context_.counters.safety_only_connections.load();

  const testing::ProbeReply stop =
      testing::http_probe(server_->port(), verb::post, "/api/haptic/stop");
  EXPECT_NE(stop.body.find("haptic playback is not available"), std::string::npos)
      << stop.error << stop.body;
  EXPECT_EQ(context_.counters.connections_evicted.load(), 21U)
      << "the stop's connection evicted one more";
}

}  // namespace
}  // namespace rig::api
