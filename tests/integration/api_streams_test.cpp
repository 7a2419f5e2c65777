// rigd's live streams: WebSocket batches and camera frames, PlotJuggler UDP, Prometheus
// metrics, and a client that stops reading cannot stall the loop or the other clients.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <nlohmann/json.hpp>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/ip/udp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <chrono>
#include <regex>

#include "rig_processes.hpp"
#include "ws_client.hpp"

namespace rig {
namespace {

namespace beast = boost::beast;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

using testing::WsClient;

std::int64_t metric(const std::string& text, const std::string& name) {
  std::smatch m;
  return std::regex_search(text, m, std::regex(name + R"( (\d+))")) ? std::stoll(m[1].str()) : -1;
}

TEST(LiveStreams, WebSocketBatchesCarryEverySampleWithItsTimeModelAndResidualAndCameraFrames) {
  testing::ScratchDir dir("streams-ws");
  testing::RigProcesses rig(dir);
  WsClient client(rig.url());
  std::size_t samples = 0, frames = 0, batches = 0;
  std::int64_t last_cycle = -1;
  bool contiguous = true, model_seen = false;
  const auto end = Clock::now() + std::chrono::seconds(2);
  while (Clock::now() < end) {
    const json m = client.next();
    if (m["type"] == "model") model_seen = true;
    if (m["type"] == "frame") ++frames;
    if (m["type"] != "samples") continue;
    ++batches;
    EXPECT_EQ(m["t_s"].size(), m["force_N"].size());
    EXPECT_EQ(m["t_s"].size(), m["residual_N"].size());
    for (const auto& c : m["cycle"]) {
      if (last_cycle >= 0 && c.get<std::int64_t>() != last_cycle + 1) contiguous = false;
      last_cycle = c.get<std::int64_t>();
      ++samples;
    }
  }
  EXPECT_TRUE(model_seen) << "a new client gets the model curve first";
  EXPECT_TRUE(contiguous) << "no sample is skipped for a client that keeps up";
  EXPECT_GT(samples, 1500U);  // 1 kHz for 2 s, in batches of 50 ms
  EXPECT_GT(batches, 20U);
  EXPECT_GE(frames, 5U);
  EXPECT_LE(frames, 2 * 30U + 2);  // at most 30 Hz (camera_max_hz 15 in the sim config)
}

TEST(LiveStreams, PlotJugglerGetsBatchedJsonOverUdpWithAnExplicitTimestamp) {
  boost::asio::io_context io;
  boost::asio::ip::udp::socket receiver(io, {boost::asio::ip::make_address("127.0.0.1"), 0});
  const int port = receiver.local_endpoint().port();
  testing::ScratchDir dir("streams-udp");
  testing::RigProcesses rig(dir, {},
                            {"stream.udp_enabled=true", "stream.udp_port=" + std::to_string(port)});
  std::array<char, 65536> buffer{};
  for (int i = 0; i < 3; ++i) {
    const std::size_t n = receiver.receive(boost::asio::buffer(buffer));
    const json j = json::parse(std::string(buffer.data(), n));
    ASSERT_TRUE(j["timestamp"].is_number());
    ASSERT_FALSE(j["t_s"].empty());
    EXPECT_DOUBLE_EQ(j["timestamp"].get<double>(), j["t_s"].back().get<double>());
    EXPECT_EQ(j["force_N"].size(), j["t_s"].size());
  }
}

TEST(LiveStreams, AClientThatStopsReadingLosesOnlyItsOwnMessages) {
  testing::ScratchDir dir("streams-slow");
  testing::RigProcesses rig(dir);
  WsClient stuck(rig.url(), 4096);  // tiny socket buffer, never read again
  WsClient healthy(rig.url());
  const std::uint64_t cycles_before = rig.status()["loop"]["cycles"];
  std::size_t healthy_batches = 0;
  std::int64_t dropped = 0;
  const auto end = Clock::now() + std::chrono::seconds(20);
  while (Clock::now() < end && (dropped <= 0 || healthy_batches < 100)) {
    if (healthy.next()["type"] == "samples") ++healthy_batches;
    if (healthy_batches % 20 == 0)
      dropped = metric(rig.api().get("/metrics").body, "rigd_stream_messages_dropped_total");
  }
  EXPECT_GT(dropped, 0) << "the stuck client's bounded queue overflowed";
  EXPECT_GE(healthy_batches, 100U) << "the other client kept receiving";
  const json after = rig.status();
  EXPECT_GT(after["loop"]["cycles"].get<std::uint64_t>(), cycles_before + 1000);
  EXPECT_EQ(rig.api().get("/api/status").status, 200);
}

TEST(LiveStreams, AHalfSentRequestDoesNotBlockOtherClients) {
  testing::ScratchDir dir("streams-slowloris");
  testing::RigProcesses rig(dir);
  std::smatch m;
  const std::string url = rig.url();
  std::regex_search(url, m, std::regex(R"(http://([^:]+):(\d+))"));
  boost::asio::io_context io;
  boost::asio::ip::tcp::socket slow(io);
  slow.connect({boost::asio::ip::make_address(m[1].str()),
                static_cast<unsigned short>(std::stoi(m[2].str()))});
  boost::asio::write(
      slow, boost::asio::buffer(std::string("GET /api/status HTTP/1.1\r\nHost: x\r\nX-Slow: ")));
  for (int i = 0; i < 20; ++i) EXPECT_EQ(rig.api().get("/api/status").status, 200);
}

TEST(Metrics, ArePrometheusTextWithTheJitterHistogramAndDropCounters) {
  testing::ScratchDir dir("metrics");
  testing::RigProcesses rig(dir);
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  const std::string text = rig.api().get("/metrics").body;
  EXPECT_NE(text.find("# TYPE rigd_loop_wakeup_latency_us histogram"), std::string::npos);
  EXPECT_NE(text.find("rigd_loop_wakeup_latency_us_bucket{le=\"+Inf\"}"), std::string::npos);
  EXPECT_GT(metric(text, "rigd_loop_cycles_total"), 100);
  EXPECT_EQ(metric(text, "rigd_recorder_drops_total"), 0);
  EXPECT_GE(metric(text, "rigd_archive_commits_total"), 0);
  EXPECT_GE(metric(text, "rigd_archive_exposure_max_seconds"), 0);
  EXPECT_GE(metric(text, "rigd_archive_checkpoints_total"), 0);
  EXPECT_GE(metric(text, "rigd_archive_checkpoint_max_seconds"), 0);
  const auto status = nlohmann::json::parse(rig.api().get("/api/status").body);
  ASSERT_TRUE(status.contains("archive_commits")) << status.dump();
  EXPECT_EQ(status["archive_commits"]["flush_interval_ms"], 50)
      << "config/rigd.sim.toml's archive.flush_interval_ms";
  EXPECT_TRUE(status["archive_commits"].contains("checkpoints")) << status.dump();
  EXPECT_GE(metric(text, "rigd_stream_messages_dropped_total"), 0);
  EXPECT_NE(text.find("rigd_state{state=\"Idle\"} 1"), std::string::npos);
}

}  // namespace
}  // namespace rig
