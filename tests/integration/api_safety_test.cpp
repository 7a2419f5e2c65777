// Stop and e-stop always get through: with every API connection taken by idle HTTP clients
// and WebSocket streams, an e-stop on a new connection is still answered, fast, while any
// other request is turned away with a clear reason (rigd + rig-sim as processes).
#include <gtest/gtest.h>

#include <boost/asio/ip/tcp.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <regex>
#include <vector>

#include "rig_processes.hpp"
#include "ws_client.hpp"

namespace rig {
namespace {

using Clock = std::chrono::steady_clock;

struct IdleClients {
  boost::asio::io_context io;
  std::vector<std::unique_ptr<boost::asio::ip::tcp::socket>> sockets;
  IdleClients(const std::string& url, int count) {
    std::smatch m;
    std::regex_search(url, m, std::regex(R"(http://([^:]+):(\d+))"));
    const boost::asio::ip::tcp::endpoint at(boost::asio::ip::make_address(m[1].str()), static_cast<unsigned short>(std::stoi(m[2].str())));
    for (int i = 0; i < count; ++i) {
      sockets.push_back(std::make_unique<boost::asio::ip::tcp::socket>(io));
      sockets.back()->connect(at);  // connected, never sends a byte
    }
  }
};

TEST(ApiSafety, AnEStopIsAnsweredWhileEveryConnectionIsTakenByIdleAndStreamingClients) {
  testing::ScratchDir dir("api-safety");
  testing::RigProcesses rig(dir, {}, {"api.max_clients=16"});
  std::vector<std::unique_ptr<testing::WsClient>> streams;
  for (int i = 0; i < 4; ++i) streams.push_back(std::make_unique<testing::WsClient>(rig.url()));
  IdleClients idle(rig.url(), 12 + 40);  // the 12 slots left, and 40 more waiting beyond the limit
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // rigd has accepted them all

  const auto refused = rig.api().get("/api/status");
  EXPECT_EQ(refused.status, 503) << refused.body;
  EXPECT_NE(refused.body.find("only stop and e-stop"), std::string::npos) << refused.body;

  std::vector<double> latency_ms;
  for (int i = 0; i < 5; ++i) {
    const auto start = Clock::now();
    const auto reply = rig.api().post("/api/estop");
    latency_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start).count());
    EXPECT_EQ(reply.status, 200) << reply.body;
  }
  std::sort(latency_ms.begin(), latency_ms.end());
  std::printf("e-stop with every connection taken: median %.1f ms, max %.1f ms\n", latency_ms[2], latency_ms[4]);
  EXPECT_LT(latency_ms[2], 100.0) << "median e-stop answer time";

  idle.sockets.clear();
  streams.clear();
  EXPECT_TRUE(rig.wait_state("EStop", 5)) << "the e-stop reached the loop";
}

}  // namespace
}  // namespace rig
