// bench-load: N WebSocket clients on rigd at 1 kHz sampling while the simulated rig cuts
// back to back, against the same with no clients. Prints loop jitter (both), dropped stream
// messages, whether the recorder lost any sample (archived samples vs loop cycles of every
// run), and the sample-to-client latency (CLOCK_MONOTONIC: sample time -> message received).
//   bench-load [--clients 20] [--seconds 60]
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <boost/asio/connect.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/websocket.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <mutex>
#include <regex>
#include <thread>

#include "api_client.hpp"
#include "archive.hpp"
#include "child_process.hpp"

namespace {

namespace beast = boost::beast;
using nlohmann::json;

double monotonic_s() {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct Latencies {
  std::mutex mutex;
  std::vector<double> ms;
  std::atomic<std::uint64_t> messages{0};
};

void client(const std::string& host, const std::string& port, std::atomic<bool>& stop,
            Latencies& out) {
  try {
    boost::asio::io_context io;
    beast::websocket::stream<beast::tcp_stream> ws(io);
    boost::asio::ip::tcp::resolver resolver(io);
    beast::get_lowest_layer(ws).connect(resolver.resolve(host, port));
    ws.handshake(host, "/ws");
    beast::flat_buffer buffer;
    std::vector<double> mine;
    while (!stop.load()) {
      ws.read(buffer);
      const double now = monotonic_s();
      const json m = json::parse(beast::buffers_to_string(buffer.data()), nullptr, false);
      buffer.consume(buffer.size());
      out.messages.fetch_add(1);
      if (m.is_object() && m.value("type", "") == "samples" && !m["t_s"].empty()) {
        mine.push_back(1e3 * (now - (m["loop_start_monotonic_s"].get<double>() +
                                     m["t_s"].back().get<double>())));
      }
    }
    std::lock_guard lock(out.mutex);
    out.ms.insert(out.ms.end(), mine.begin(), mine.end());
  } catch (const std::exception&) {
  }
}

struct Phase {
  double p50 = 0, p99 = 0, p999 = 0, max = 0;
  std::int64_t overruns = 0, ws_dropped = 0, runs = 0, samples = 0, gaps = 0;
  double latency_p50 = 0, latency_p99 = 0;
  std::uint64_t messages = 0;
};

void cut_back_to_back(const rig::cli::ApiClient& api, double seconds) {
  api.post("/api/home");
  for (int i = 0; i < 600 && json::parse(api.get("/api/status").body)["state"] != "Ready"; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  api.post("/api/tare");
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    const auto state = json::parse(api.get("/api/status").body)["state"];
    if (state == "Ready" || state == "Done")
      api.post("/api/run", R"({"eye_id":"LOAD","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":12})");
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
  api.post("/api/stop");
}

Phase measure(int clients, double seconds, const std::string& bin, const std::string& source) {
  const std::string dir = "/tmp/bench-load-" + std::to_string(clients);
  std::system(("rm -rf " + dir + " && mkdir -p " + dir).c_str());
  rig::cli::ChildProcess sim({bin + "/rig-sim", "--port", "0"}, dir + "/sim.log");
  const std::string sim_line = sim.wait_for_line("listening on", 10000);
  rig::cli::ChildProcess rigd(
      {bin + "/rigd", "--config", source + "/config/rigd.sim.toml", "--set",
       "daq.port=" + sim_line.substr(sim_line.rfind(':') + 1), "--set", "api.port=0", "--set",
       "archive.path=\"" + dir + "/archive.sqlite\""},
      dir + "/rigd.log");
  const std::string ready = rigd.wait_for_line("ready, API on", 20000);
  const std::string url = ready.substr(ready.find("http://"));
  std::smatch m;
  std::regex_search(url, m, std::regex(R"(http://([^:]+):(\d+))"));
  const rig::cli::ApiClient api(url, "");
  Latencies latencies;
  std::atomic<bool> stop{false};
  std::vector<std::thread> threads;
  for (int i = 0; i < clients; ++i)
    threads.emplace_back(client, m[1].str(), m[2].str(), std::ref(stop), std::ref(latencies));
  cut_back_to_back(api, seconds);
  const json status = json::parse(api.get("/api/status").body);
  const std::string metrics = api.get("/metrics").body;
  stop.store(true);
  rigd.stop();  // closes the sockets: the clients' reads end
  for (auto& t : threads) t.join();
  Phase p;
  p.p50 = status["loop"]["jitter_p50_us"];
  p.p99 = status["loop"]["jitter_p99_us"];
  p.p999 = status["loop"]["jitter_p999_us"];
  p.max = status["loop"]["jitter_max_us"];
  p.overruns = status["loop"]["overruns"];
  std::smatch dropped;
  if (std::regex_search(metrics, dropped,
                        std::regex(R"(rigd_stream_messages_dropped_total (\d+))")))
    p.ws_dropped = std::stoll(dropped[1].str());
  rig::archive::Archive archive(dir + "/archive.sqlite", true);
  for (const auto& run : archive.list_runs()) {
    if (run.samples == 0) continue;
    ++p.runs;
    p.samples += run.samples;
    // Every loop cycle of a run is archived: cycle numbers run without gaps.
    auto q = rig::archive::Database(dir + "/archive.sqlite", true)
                 .prepare("SELECT MIN(idx), MAX(idx), COUNT(*) FROM samples WHERE run_id = ?");
    q.bind(1, run.id);
    q.step();
    p.gaps += (q.integer(1) - q.integer(0) + 1) - q.integer(2);
  }
  std::sort(latencies.ms.begin(), latencies.ms.end());
  if (!latencies.ms.empty()) {
    p.latency_p50 = latencies.ms[latencies.ms.size() / 2];
    p.latency_p99 = latencies.ms[latencies.ms.size() * 99 / 100];
  }
  p.messages = latencies.messages.load();
  sim.stop();
  return p;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"bench-load: WebSocket clients against rigd while it cuts"};
  int clients = 20;
  double seconds = 60;
  app.add_option("--clients", clients, "WebSocket clients");
  app.add_option("--seconds", seconds, "duration of each phase [s]");
  CLI11_PARSE(app, argc, argv);
  const std::string bin = RIG_BIN_DIR, source = RIG_SOURCE_DIR;
  std::printf("%-12s %8s %8s %9s %9s %9s %11s %6s %9s %6s %12s %12s\n", "clients", "p50_us",
              "p99_us", "p99.9_us", "max_us", "overruns", "ws_dropped", "runs", "samples", "gaps",
              "lat_p50_ms", "lat_p99_ms");
  for (const int n : {0, clients}) {
    const Phase p = measure(n, seconds, bin, source);
    std::printf("%-12d %8.0f %8.0f %9.0f %9.0f %9lld %11lld %6lld %9lld %6lld %12.2f %12.2f\n", n,
                p.p50, p.p99, p.p999, p.max, static_cast<long long>(p.overruns),
                static_cast<long long>(p.ws_dropped), static_cast<long long>(p.runs),
                static_cast<long long>(p.samples), static_cast<long long>(p.gaps), p.latency_p50,
                p.latency_p99);
    std::fflush(stdout);
  }
  std::printf(
      "(%.0f s each, rigd at 1 kHz on the simulated rig over Modbus TCP; gaps = loop cycles of a "
      "run missing from the archive)\n",
      seconds);
  return 0;
}
