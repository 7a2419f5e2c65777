#include "status_view.hpp"

#include <nlohmann/json.hpp>

#include <cmath>
#include <sstream>

#include "json_text.hpp"
#include "recorder.hpp"
#include "rig/proto/messages.hpp"

namespace rig::api {

namespace {

double ms(const std::atomic<std::int64_t>& us) {
  return static_cast<double>(us.load(std::memory_order_relaxed)) / 1000.0;
}

proto::ArchiveCommits archive_commits(const service::RecorderStats& r, int flush_interval_ms) {
  proto::ArchiveCommits a;
  a.commits = static_cast<std::int64_t>(r.commits.load());
  a.samples_written = static_cast<std::int64_t>(r.samples_written.load());
  a.flush_interval_ms = flush_interval_ms;
  a.last_commit_ms = ms(r.last_commit_us);
  a.max_commit_ms = ms(r.max_commit_us);
  a.max_late_ms = ms(r.max_late_us);
  a.last_exposure_ms = ms(r.last_exposure_us);
  a.max_exposure_ms = ms(r.max_exposure_us);
  a.checkpoints = static_cast<std::int64_t>(r.checkpoints.load());
  a.max_checkpoint_ms = ms(r.max_checkpoint_us);
  return a;
}

}  // namespace

std::string status_json(ApiContext& c) {
  const rt::StatusSnapshot st = c.channels->status.read();
  const auto jitter = c.channels->jitter.snapshot();
  const rt::LoopCounters& n = c.channels->counters;
  proto::Status s;
  s.state = std::string(rt::to_string(st.state));
  s.phase = std::string(rt::to_string(st.phase));
  s.fault =
      st.fault == rt::FaultCode::kNone ? "none" : service::describe_fault(st.fault, st.fault_value);
  s.fault_value = st.fault_value;
  s.homed = st.homed;
  s.tared = st.tared;
  s.taring = st.taring;
  s.position_mm = st.position_mm;
  s.velocity_mm_s = st.velocity_mm_s;
  s.force_N = st.force_N;
  s.iop_mmHg = st.iop_mmHg;
  s.iop_target_mmHg = st.iop_target_mmHg;
  s.iop_settled = st.iop_settled;
  s.motor_volts = st.motor_volts;
  s.motor_enabled = st.motor_enabled;
  s.pump_command = st.pump_command;
  s.run_id = st.run_id;
  s.interlocks = {st.home_limit, st.end_limit, st.estop_input, st.io_ok, st.consecutive_misses};
  s.loop.rate_hz = c.config->loop.rate_hz;
  s.loop.cycles = static_cast<std::int64_t>(n.cycles.load());
  s.loop.overruns = static_cast<std::int64_t>(n.overruns.load());
  s.loop.missed_cycles = static_cast<std::int64_t>(n.missed_cycles.load());
  s.loop.io_misses = static_cast<std::int64_t>(n.io_misses.load());
  s.loop.jitter_p50_us = jitter.percentile_us(0.5);
  s.loop.jitter_p99_us = jitter.percentile_us(0.99);
  s.loop.jitter_p999_us = jitter.percentile_us(0.999);
  s.loop.jitter_max_us = static_cast<double>(jitter.max_ns) / 1000.0;
  s.loop.realtime = c.realtime;
  s.recorder_drops = static_cast<std::int64_t>(n.recorder_drops.load());
  s.stream_drops = static_cast<std::int64_t>(n.stream_drops.load());
  s.version = c.version;
  s.config_hash = c.config->hash;
  const auto model = c.hub->model();
  s.model_file = model ? model->path : "";
  s.surface_mm = c.config->loop.motion.surface_mm;
  // Validated against proto::LabArchiveStatus, so the page and `rig status` read one schema.
  if (c.lab_archive_status)
    s.lab_archive = nlohmann::json::parse(c.lab_archive_status()).get<proto::LabArchiveStatus>();
  if (c.recorder_stats)
    s.archive_commits = archive_commits(*c.recorder_stats, c.config->archive.flush_interval_ms);
  return json_text(nlohmann::json(s));
}

namespace {

// Prometheus' text format: each metric with its help and type.
class MetricsWriter {
 public:
  explicit MetricsWriter(std::ostringstream& out) : out_(out) {}
  void counter(const char* name, const char* help, double value) {
    write(name, help, "counter", value);
  }
  void gauge(const char* name, const char* help, double value) {
    write(name, help, "gauge", value);
  }

 private:
  void write(const char* name, const char* help, const char* type, double value) {
    out_ << "# HELP " << name << " " << help << "\n# TYPE " << name << " " << type << "\n"
         << name << " " << value << "\n";
  }
  std::ostringstream& out_;
};

void loop_metrics(MetricsWriter& m, const rt::LoopCounters& n) {
  m.counter("rigd_loop_cycles_total", "RT loop cycles", static_cast<double>(n.cycles.load()));
  m.counter("rigd_loop_overruns_total", "cycles that ended after the next deadline",
            static_cast<double>(n.overruns.load()));
  m.counter("rigd_loop_missed_cycles_total", "deadlines skipped after overruns",
            static_cast<double>(n.missed_cycles.load()));
  m.counter("rigd_daq_misses_total", "failed DAQ reads", static_cast<double>(n.io_misses.load()));
  m.counter("rigd_loop_late_wakes_total", "cycles begun more than half a period late",
            static_cast<double>(n.late_wakes.load()));
  m.counter("rigd_daq_misses_late_wake_total",
            "failed DAQ reads in late cycles (not held against the link)",
            static_cast<double>(n.late_wake_misses.load()));
  m.counter("rigd_recorder_drops_total", "samples the recorder could not take (faults the run)",
            static_cast<double>(n.recorder_drops.load()));
}

void archive_metrics(MetricsWriter& m, const service::RecorderStats& r) {
  m.counter("rigd_archive_commits_total", "commits of the rig's archive",
            static_cast<double>(r.commits.load()));
  m.gauge("rigd_archive_commit_max_seconds",
          "the longest commit (write + fsync) since rigd started", ms(r.max_commit_us) / 1000.0);
  m.gauge("rigd_archive_commit_late_max_seconds", "the latest a commit began after it was due",
          ms(r.max_late_us) / 1000.0);
  m.gauge("rigd_archive_exposure_max_seconds",
          "the most samples a power cut could have taken, in time", ms(r.max_exposure_us) / 1000.0);
  m.counter("rigd_archive_checkpoints_total",
            "copies of the archive's log into its database (between runs)",
            static_cast<double>(r.checkpoints.load()));
  m.gauge("rigd_archive_checkpoint_max_seconds", "the longest such copy",
          ms(r.max_checkpoint_us) / 1000.0);
}

void api_metrics(MetricsWriter& m, ApiContext& c) {
  m.counter("rigd_stream_ring_drops_total", "samples dropped before the stream hub",
            static_cast<double>(c.channels->counters.stream_drops.load()));
  m.counter("rigd_stream_messages_dropped_total", "WebSocket messages dropped for slow clients",
            static_cast<double>(c.counters.ws_messages_dropped.load()));
  m.counter("rigd_stream_messages_sent_total", "WebSocket messages sent",
            static_cast<double>(c.counters.ws_messages_sent.load()));
  m.counter("rigd_http_requests_total", "HTTP requests",
            static_cast<double>(c.counters.http_requests.load()));
  m.counter("rigd_http_unauthorized_total", "requests refused for a missing or wrong token",
            static_cast<double>(c.counters.refused_unauthorized.load()));
  m.counter("rigd_http_cross_site_refused_total",
            "requests refused by the Host / Origin / Content-Type guard",
            static_cast<double>(c.counters.refused_cross_site.load()));
  m.counter("rigd_api_handler_exceptions_total",
            "request handlers that threw past their own error handling",
            static_cast<double>(c.counters.handler_exceptions.load()));
  m.counter("rigd_api_connections_evicted_total",
            "stop/e-stop-only connections closed unread for newer ones (safety_only_queue.hpp)",
            static_cast<double>(c.counters.connections_evicted.load()));
  m.counter("rigd_api_accept_failures_total", "failed accepts (no descriptor left, ...)",
            static_cast<double>(c.counters.accept_failures.load()));
  m.gauge("rigd_api_connections", "open HTTP connections (WebSocket streams: rigd_stream_clients)",
          static_cast<double>(c.counters.open_connections.load()));
  m.gauge("rigd_api_safety_only_connections",
          "open connections refused a general slot, served stop/e-stop only",
          static_cast<double>(c.counters.safety_only_connections.load()));
  m.gauge("rigd_stream_clients", "connected WebSocket clients",
          static_cast<double>(c.counters.ws_clients.load()));
}

void state_and_latency_metrics(std::ostringstream& out, const rt::StatusSnapshot& st,
                               const rt::JitterHistogram::Snapshot& jitter) {
  MetricsWriter m(out);
  m.gauge("rigd_force_newtons", "tared force", st.force_N);
  m.gauge("rigd_position_mm", "carriage position", st.position_mm);
  m.gauge("rigd_iop_mmhg", "intraocular pressure", st.iop_mmHg);
  out << "# HELP rigd_state current run state\n# TYPE rigd_state gauge\n";
  for (int i = 0; i <= static_cast<int>(rt::RunState::kEStop); ++i) {
    const auto state = static_cast<rt::RunState>(i);
    out << "rigd_state{state=\"" << rt::to_string(state) << "\"} " << (state == st.state ? 1 : 0)
        << "\n";
  }
  out << "# HELP rigd_loop_wakeup_latency_us wake-up latency of the RT loop\n# TYPE "
         "rigd_loop_wakeup_latency_us histogram\n";
  std::uint64_t cumulative = 0;
  for (int bin = 0; bin < rt::JitterHistogram::kBinCount - 1; ++bin) {
    cumulative += jitter.counts[static_cast<std::size_t>(bin)];
    if (jitter.counts[static_cast<std::size_t>(bin)] == 0 && bin % 8 != 7) continue;
    out << "rigd_loop_wakeup_latency_us_bucket{le=\"" << rt::JitterHistogram::upper_edge_us(bin)
        << "\"} " << cumulative << "\n";
  }
  out << "rigd_loop_wakeup_latency_us_bucket{le=\"+Inf\"} " << jitter.total << "\n";
  out << "rigd_loop_wakeup_latency_us_count " << jitter.total << "\n";
}

}  // namespace

std::string prometheus_metrics(ApiContext& c) {
  std::ostringstream out;
  MetricsWriter m(out);
  loop_metrics(m, c.channels->counters);
  if (const service::RecorderStats* r = c.recorder_stats) archive_metrics(m, *r);
  api_metrics(m, c);
  state_and_latency_metrics(out, c.channels->status.read(), c.channels->jitter.snapshot());
  if (c.extra_metrics) out << c.extra_metrics();
  return out.str();
}

}  // namespace rig::api
