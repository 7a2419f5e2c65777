// Stop and e-stop always get through (issue 14), rigd + rig-sim as processes: with far more
// connections than every cap (idle, slow-loris, WebSocket streams that read and that never
// read, a flood that keeps coming), and while a large run is exported, each stop and e-stop on
// a new connection is answered 200 within 100 ms, while any other request is turned away with
// a clear reason. (During a large export: api_export_safety_test.cpp, load tier.)
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "http_probe.hpp"
#include "rig_processes.hpp"
#include "safety_answers.hpp"
#include "silent_clients.hpp"
#include "streaming_clients.hpp"

namespace rig {
namespace {

using boost::beast::http::verb;
using Clock = std::chrono::steady_clock;
using testing::expect_each_answered_in_time;

double metric(const std::string& metrics, const std::string& name) {
  const auto at = metrics.find("\n" + name + " ");
  return at == std::string::npos ? -1.0 : std::stod(metrics.substr(at + name.size() + 2));
}

TEST(
    ApiSafety,
    AStopAndEveryEStopAreAnsweredWithin100msWhileHundredsOfIdleSlowAndStreamingConnectionsFloodRigd) {
  testing::ScratchDir dir("api-safety-flood");
  testing::RigProcesses rig(dir, {}, {"api.max_clients=16", "api.max_clients_per_address=8"});
  const int port = testing::port_of(rig.url());
  std::vector<testing::ProbeReply> stops;
  std::vector<testing::ProbeReply> estops;
  {
    testing::StreamingClients streams(port, "127.0.0.2", 4, 4);  // 127.0.0.2 at its cap of 8
    testing::SilentClients silent(port);
    silent.open_slow_loris("127.0.0.3", 8);  // 16: every general slot is taken
    for (int i = 0; i < 150; ++i) {          // 300 more, far past every cap, from 2 addresses
      silent.open_idle("127.0.0.1", 1);
      silent.open_slow_loris("127.0.0.4", 1);
    }
    std::atomic<bool> flooding{true};  // and more keep coming, 200 a second, while we stop
    std::thread flood([&] {
      while (flooding.load()) {
        silent.open_idle("127.0.0.5", 1);
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
      }
    });
    std::this_thread::sleep_for(std::chrono::milliseconds(200));  // rigd has accepted them all

    const testing::ProbeReply refused = testing::http_probe(port, verb::get, "/api/status");
    EXPECT_EQ(refused.status, 503) << refused.error << refused.body;
    EXPECT_NE(refused.body.find("only stop and e-stop"), std::string::npos) << refused.body;
    stops.push_back(testing::http_probe(port, verb::post, "/api/stop"));
    for (int i = 0; i < 10; ++i) {
      estops.push_back(testing::http_probe(port, verb::post, "/api/estop",
                                           i % 2 == 0 ? "127.0.0.1" : "127.0.0.4"));
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
    flooding.store(false);
    flood.join();
    EXPECT_GT(streams.messages_read(), 0U) << "the streams were served meanwhile";
    EXPECT_GT(silent.closed_by_server_count(), 200)
        << "of " << silent.count() << ": rigd evicted the oldest";
  }  // every client closes its connections
  expect_each_answered_in_time(stops, "stop with every connection taken and a flood");
  expect_each_answered_in_time(estops, "e-stop with every connection taken and a flood");
  EXPECT_TRUE(rig.wait_state("EStop", 5)) << "the e-stop reached the loop";
  const std::string metrics = rig.api().get("/metrics").body;
  EXPECT_GT(metric(metrics, "rigd_api_connections_evicted_total"), 200.0) << metrics;
}

}  // namespace
}  // namespace rig
