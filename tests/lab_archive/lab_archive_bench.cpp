// ./rig bench lab-archive: N simulated rigs (default 10) each recording 1 kHz x every channel
// into its own SQLite archive, each with rigd's replicator shipping to one PostgreSQL 15 on
// this machine (a throwaway server). Prints the sustained rate, replication lag p50/p99
// (local commit -> on the server), the server's CPU, the drain rate of a backlog (headroom),
// and the time of `rig model diagnose` over the same runs from PostgreSQL and from SQLite.
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <thread>

#include "command.hpp"
#include "lab_replicator.hpp"
#include "pg_test_server.hpp"
#include "server_cpu_meter.hpp"
#include "streaming_rig.hpp"
#include "test_paths.hpp"

namespace {

using rig::testing::StreamingRig;
using Clock = StreamingRig::Clock;

struct Options {
  int rigs = 10;
  double seconds = 20.0;
  double rate_hz = 1000.0;
  int flush_ms = 50;
  std::int64_t backlog_samples = 200000;  // per rig, for the drain (headroom) phase
  int diagnose_runs = 1000;
};

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1,
                         static_cast<std::size_t>(p * static_cast<double>(values.size())))];
}

rig::lab_archive::LabArchiveSettings settings(const rig::testing::PgTestServer& server, int rig) {
  rig::lab_archive::LabArchiveSettings s;
  s.enabled = true;
  s.conninfo = server.conninfo();
  s.sslmode = "disable";
  s.rig_id = "bench-rig-" + std::to_string(rig);
  return s;  // interval, batch and retry as rigd's defaults
}

// The 1, 5 and 15 minute load averages, as /proc/loadavg gives them.
std::string load_average() {
  std::ifstream in("/proc/loadavg");
  std::string one, five, fifteen;
  in >> one >> five >> fifteen;
  return one + " " + five + " " + fifteen;
}

// Polls the server's watermarks every 20 ms; a batch's lag is from its local commit to the
// first poll that sees it on the server.
std::vector<double> measure_lags(const rig::testing::PgTestServer& server,
                                 std::vector<std::unique_ptr<StreamingRig>>& rigs, double seconds) {
  rig::lab_archive::PgConnection db(server.conninfo());
  std::vector<std::vector<std::pair<std::int64_t, Clock::time_point>>> arrivals(rigs.size());
  const auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (Clock::now() < end) {
    auto rows =
        db.query("SELECT rig_id, max(last_idx) FROM runs GROUP BY rig_id", {}, "poll watermarks");
    const auto now = Clock::now();
    for (int r = 0; r < rows.rows(); ++r) {
      const auto index = static_cast<std::size_t>(std::stoi(rows.text(r, 0).substr(10)));
      arrivals[index].emplace_back(rows.integer(r, 1), now);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  std::vector<double> lags;
  for (std::size_t i = 0; i < rigs.size(); ++i) {
    for (const auto& commit : rigs[i]->commits()) {
      const auto hit = std::find_if(arrivals[i].begin(), arrivals[i].end(),
                                    [&](const auto& a) { return a.first >= commit.last_idx; });
      if (hit == arrivals[i].end())
        continue;  // committed near the end: not shipped within the window
      lags.push_back(std::chrono::duration<double>(hit->second - commit.at).count() * 1e3);
    }
  }
  return lags;
}

// CPU seconds (user + system) of this process: the replicators' threads while draining.
double own_cpu_seconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  auto seconds = [](const timeval& t) {
    return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_usec) * 1e-6;
  };
  return seconds(usage.ru_utime) + seconds(usage.ru_stime);
}

// Headroom: a backlog per rig (as after a long cut), then every replicator drains at once.
void drain_phase(const Options& o, rig::testing::PgTestServer& server,
                 std::vector<std::unique_ptr<StreamingRig>>& rigs) {
  for (auto& rig : rigs) rig->append_now(o.backlog_samples);
  rig::lab_archive::PgConnection db(
      server.conninfo());  // polled: a psql per poll would cost CPU the drain needs
  auto on_server = [&db] {
    return db
        .query("SELECT coalesce(sum(samples), 0) FROM runs", {}, "count the samples on the server")
        .integer(0, 0);
  };
  rig::testing::ServerCpuMeter cpu(server.dir() + "/data");
  const std::int64_t total_before = on_server();
  const double server_cpu_before = cpu.cpu_seconds();
  const double client_cpu_before = own_cpu_seconds();
  const auto drain_start = Clock::now();
  std::vector<std::unique_ptr<rig::lab_archive::LabReplicator>> replicators;
  for (std::size_t r = 0; r < rigs.size(); ++r) {
    replicators.push_back(std::make_unique<rig::lab_archive::LabReplicator>(
        settings(server, static_cast<int>(r)), rigs[r]->path(), "bench"));
    replicators.back()->start();
  }
  std::int64_t written = 0;
  for (auto& rig : rigs) written += rig->samples();
  while (on_server() < written) std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const double drain_s = std::chrono::duration<double>(Clock::now() - drain_start).count();
  const double server_cpu = cpu.cpu_seconds() - server_cpu_before;
  const double client_cpu = own_cpu_seconds() - client_cpu_before;
  const auto drained = static_cast<double>(written - total_before);
  const double drain_rate = drained / drain_s;
  const double combined_rate = o.rigs * o.rate_hz;
  std::printf(
      "drain: %d x %lld samples backlog in %.1f s = %.0f samples/s, headroom %.1fx the rigs' "
      "combined rate\n",
      o.rigs, static_cast<long long>(o.backlog_samples), drain_s, drain_rate,
      drain_rate / combined_rate);
  // The rigs' replicators share this machine with the server here; on a lab's network they
  // do not, and the server's own cost per sample bounds what one server takes.
  const double server_rate = drained / std::max(server_cpu, 1e-3);
  std::printf(
      "  server CPU while draining %.1f s: %.0f samples per server CPU-second = %.0fx the rigs' "
      "rate per core\n",
      server_cpu, server_rate, server_rate / combined_rate);
  std::printf(
      "  replicators' CPU while draining %.1f s: %.0f samples per replicator CPU-second; load "
      "average %s\n",
      client_cpu, drained / std::max(client_cpu, 1e-3), load_average().c_str());
  for (auto& replicator : replicators) replicator->stop();
}

void streaming_phase(const Options& o, rig::testing::PgTestServer& server,
                     const rig::testing::ScratchDir& dir) {
  std::vector<std::unique_ptr<StreamingRig>> rigs;
  std::vector<std::unique_ptr<rig::lab_archive::LabReplicator>> replicators;
  for (int r = 0; r < o.rigs; ++r) {
    rigs.push_back(std::make_unique<StreamingRig>(dir.file("rig" + std::to_string(r) + ".sqlite"),
                                                  o.rate_hz, o.flush_ms));
    replicators.push_back(std::make_unique<rig::lab_archive::LabReplicator>(
        settings(server, r), rigs.back()->path(), "bench"));
    replicators.back()->start();
  }
  rig::testing::ServerCpuMeter cpu(server.dir() + "/data");
  std::this_thread::sleep_for(std::chrono::seconds(1));  // connected, schema made
  const std::int64_t shipped_before =
      std::stoll(server.query("SELECT coalesce(sum(samples), 0) FROM runs"));
  const double cpu_before = cpu.cpu_seconds();
  const auto start = Clock::now();
  for (auto& rig : rigs) rig->start();
  const std::vector<double> lags = measure_lags(server, rigs, o.seconds);
  const double wall = std::chrono::duration<double>(Clock::now() - start).count();
  const double cpu_used = cpu.cpu_seconds() - cpu_before;
  const std::int64_t shipped =
      std::stoll(server.query("SELECT coalesce(sum(samples), 0) FROM runs")) - shipped_before;
  for (auto& rig : rigs) rig->stop();
  std::printf("streaming: %d rigs x %.0f Hz x 11 channels for %.1f s\n", o.rigs, o.rate_hz, wall);
  std::printf("  sustained %.0f samples/s into PostgreSQL (offered %.0f)\n",
              static_cast<double>(shipped) / wall, o.rigs * o.rate_hz);
  std::printf(
      "  replication lag (local commit -> on the server): p50 %.0f ms, p99 %.0f ms, max %.0f ms "
      "(%zu batches)\n",
      percentile(lags, 0.5), percentile(lags, 0.99), percentile(lags, 1.0), lags.size());
  std::printf("  server CPU %.0f%% of one core (%.1f s in %.1f s; machine has %ld cores)\n",
              100.0 * cpu_used / wall, cpu_used, wall, sysconf(_SC_NPROCESSORS_ONLN));
  for (auto& replicator : replicators) replicator->stop();
  drain_phase(o, server, rigs);
}

}  // namespace

int diagnose_phase(int runs, rig::testing::PgTestServer& server,
                   const rig::testing::ScratchDir& dir);  // lab_archive_bench_diagnose.cpp

// Ctrl-C (or a stop) must not leave the throwaway server running: the signals are taken by
// one thread, which stops the server and removes its files and the scratch folder.
void stop_server_on_interrupt(rig::testing::PgTestServer& server,
                              const rig::testing::ScratchDir& dir, const sigset_t& signals) {
  std::thread([&server, &dir, signals] {
    int signal_number = 0;
    if (sigwait(&signals, &signal_number) != 0) return;
    std::fprintf(stderr, "bench-lab-archive: interrupted: stopping the throwaway PostgreSQL\n");
    try {
      server.stop("immediate");
    } catch (const std::exception&) {  // already down: its files still go
    }
    std::error_code ignored;
    std::filesystem::remove_all(server.dir(), ignored);
    std::filesystem::remove_all(dir.path(), ignored);
    _exit(128 + signal_number);
  }).detach();
}

int main(int argc, char** argv) {
  CLI::App app{
      "lab archive throughput, replication lag and server CPU on one PostgreSQL "
      "(docs/lab-archive.md)"};
  Options o;
  app.add_option("--rigs", o.rigs, "simulated rigs")->check(CLI::Range(1, 50));
  app.add_option("--seconds", o.seconds, "streaming time [s]")->check(CLI::Range(2.0, 3600.0));
  app.add_option("--rate-hz", o.rate_hz, "samples per second per rig")
      ->check(CLI::Range(10.0, 20000.0));
  app.add_option("--backlog", o.backlog_samples, "samples per rig for the drain phase")
      ->check(CLI::Range(1000, 10000000));
  app.add_option("--diagnose-runs", o.diagnose_runs,
                 "runs for diagnose from PostgreSQL vs SQLite (0: skip)")
      ->check(CLI::Range(0, 100000));
  CLI11_PARSE(app, argc, argv);
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);  // before any thread starts: every one inherits it
  try {
    rig::testing::ScratchDir dir("bench-lab-archive");
    rig::testing::PgTestServer server(true);  // fsync on, as a lab's server
    stop_server_on_interrupt(server, dir, signals);
    streaming_phase(o, server, dir);
    return o.diagnose_runs > 0 ? diagnose_phase(o.diagnose_runs, server, dir) : 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench-lab-archive: %s\n", e.what());
    return 1;
  }
}
