#pragma once
// What the API reaches: the loop's channels, the stream hub, the config, and its own
// counters. Everything here is either immutable after setup or thread-safe.
#include <atomic>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "auth.hpp"
#include "loop_channels.hpp"
#include "recorder_stats.hpp"
#include "request_guard.hpp"
#include "rig/config/rigd_config.hpp"
#include "stream_hub.hpp"

namespace rig::api {

struct ApiCounters {
  std::atomic<std::uint64_t> http_requests{0};
  std::atomic<std::uint64_t> refused_unauthorized{0};
  std::atomic<std::uint64_t> refused_invalid{0};
  std::atomic<std::uint64_t> refused_cross_site{0};  // Host / Origin / Content-Type guard
  std::atomic<std::uint64_t> handler_exceptions{0};  // caught at the I/O thread's top
  std::atomic<std::int64_t> ws_clients{0};
  std::atomic<std::uint64_t> ws_messages_sent{0};
  std::atomic<std::uint64_t> ws_messages_dropped{0};  // slow clients: oldest batches dropped
  std::atomic<std::int64_t> open_connections{0};
  std::atomic<std::int64_t> safety_only_connections{
      0};                                             // refused a general slot: stop / e-stop only
  std::atomic<std::uint64_t> connections_evicted{0};  // safety-only ones closed for newer ones
  std::atomic<std::uint64_t> accept_failures{0};      // accept() errors, e.g. no descriptor left
};

class LabService;     // model lab requests (non-RT worker), optional
class HapticControl;  // haptic playback sessions, optional

struct ApiContext {
  rt::LoopChannels* channels = nullptr;
  service::StreamHub* hub = nullptr;
  const config::RigdConfig* config = nullptr;
  LabService* lab = nullptr;
  HapticControl* haptic = nullptr;
  bool realtime = false;
  std::string version;
  ApiAuth auth{std::nullopt};
  RequestGuard guard{"", ""};  // CSRF / DNS-rebinding checks (request_guard.hpp)
  ApiCounters counters;
  const service::RecorderStats* recorder_stats =
      nullptr;                                 // the archive's commit timing, when recording
  std::function<std::string()> extra_metrics;  // driver counters in Prometheus text
  std::function<std::string()>
      lab_archive_status;  // JSON object when [lab_archive] is on (status "lab_archive")
  // libpq keyword/value pairs of the lab archive (lab_archive::connection_params); empty: off.
  std::vector<std::pair<std::string, std::string>> lab_archive_connection;
};

}  // namespace rig::api
