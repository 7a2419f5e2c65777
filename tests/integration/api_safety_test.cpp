// Stop and e-stop always get through (issue 14), rigd + rig-sim as processes: with far more
// connections than every cap (idle, slow-loris, WebSocket streams that read and that never
// read, a flood that keeps coming), and while a large run is exported, each stop and e-stop on
// a new connection is answered 200 within 100 ms, while any other request is turned away with
// a clear reason.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "archive.hpp"
#include "http_probe.hpp"
#include "rig_processes.hpp"
#include "silent_clients.hpp"
#include "streaming_clients.hpp"

namespace rig {
namespace {

using boost::beast::http::verb;
using Clock = std::chrono::steady_clock;

constexpr double kSafetyAnswerBound_ms = 100.0;  // issue 14: stop / e-stop answered within this

// Every reply 200 within the bound, each one (not a median), counted from the established
// connection: its connect is the kernel's and this client's (on a 2-core VM shared with
// builds, a loopback connect alone once took 2 s: the test's own thread waited for a CPU).
// Prints median and worst of both.
void expect_each_answered_in_time(const std::vector<testing::ProbeReply>& replies,
                                  const std::string& what) {
  std::vector<double> answer_ms;
  std::vector<double> connect_ms;
  for (std::size_t i = 0; i < replies.size(); ++i) {
    const testing::ProbeReply& r = replies[i];
    EXPECT_EQ(r.status, 200) << what << " #" << i << ": " << r.error << r.body;
    EXPECT_LT(r.took_ms - r.connected_ms, kSafetyAnswerBound_ms)
        << what << " #" << i << " answer time after connecting [ms] (connect: " << r.connected_ms
        << " ms)";
    answer_ms.push_back(r.took_ms - r.connected_ms);
    connect_ms.push_back(r.connected_ms);
  }
  std::sort(answer_ms.begin(), answer_ms.end());
  std::sort(connect_ms.begin(), connect_ms.end());
  if (answer_ms.empty()) return;
  std::printf("%s: %zu answered, median %.1f ms, worst %.1f ms (connect: median %.1f, worst %.1f)\n",
              what.c_str(), answer_ms.size(), answer_ms[answer_ms.size() / 2], answer_ms.back(),
              connect_ms[connect_ms.size() / 2], connect_ms.back());
}

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

model::RunData long_run(std::size_t samples) {
  model::RunData run;
  run.source = "long.csv";
  run.set("eye_id", "LONG");
  run.t_s.resize(samples);
  run.x_mm.resize(samples);
  run.force_N.resize(samples);
  for (std::size_t i = 0; i < samples; ++i) {
    run.t_s[i] = static_cast<double>(i) * 1e-3;
    run.x_mm[i] = static_cast<double>(i) * 1e-5;
    run.force_N[i] = 0.1 + static_cast<double>(i % 1000) * 1e-4;
  }
  return run;
}

// Lines of a run-CSV that are neither metadata ("# key: value") nor the column header.
std::size_t sample_lines(const std::string& csv) {
  std::size_t lines = 0;
  for (std::size_t at = 0; at < csv.size();) {
    const std::size_t end = std::min(csv.find('\n', at), csv.size());
    if (csv[at] != '#') ++lines;
    at = end + 1;
  }
  return lines == 0 ? 0 : lines - 1;
}

TEST(ApiSafety, EveryEStopIsAnsweredWithin100msWhileALargeRunIsExportedAsCsv) {
  testing::ScratchDir dir("api-safety-export");
  constexpr std::size_t kSamples = 1'000'000;  // ~17 min at 1 kHz: seconds to read and format
  std::int64_t run_id = 0;
  {
    archive::Archive archive(dir.file("archive.sqlite"));  // RigProcesses' archive path
    run_id = archive.import_run(long_run(kSamples));
  }
  testing::RigProcesses rig(dir);
  const int port = testing::port_of(rig.url());

  std::atomic<bool> exporting{true};
  cli::HttpReply csv;
  double export_s = 0.0;
  std::thread exporter([&] {
    const auto start = Clock::now();
    csv = rig.api().get("/api/runs/" + std::to_string(run_id) + "/csv");
    export_s = std::chrono::duration<double>(Clock::now() - start).count();
    exporting.store(false);
  });
  std::vector<testing::ProbeReply> estops;
  while (exporting.load()) {
    estops.push_back(testing::http_probe(port, verb::post, "/api/estop"));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  exporter.join();
  std::printf("export of %zu samples: %.2f s, %zu bytes\n", kSamples, export_s, csv.body.size());
  EXPECT_EQ(csv.status, 200) << csv.body.substr(0, 300);
  EXPECT_EQ(sample_lines(csv.body), kSamples) << "every sample exported";
  EXPECT_GE(estops.size(), 5U) << "the export lasted long enough to e-stop during it";
  expect_each_answered_in_time(estops, "e-stop during a large export");
}

}  // namespace
}  // namespace rig
