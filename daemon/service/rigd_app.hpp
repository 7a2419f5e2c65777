#pragma once
// rigd's wiring: config -> drivers -> RT loop (on its RT thread) -> recorder, stream hub,
// API server. Exceptions only here, at setup; once running, failures are statuses and
// faults. Signals are handled by main (sigwait), which calls shutdown().
#include <atomic>
#include <memory>
#include <thread>

#include "api_context.hpp"
#include "rig/config/rigd_config.hpp"

namespace rig::service {

class RigdApp {
 public:
  explicit RigdApp(config::RigdConfig config);
  ~RigdApp();
  void start();     // throws with a clear message if any part cannot start
  void shutdown();  // motor off, flush the archive, stop the threads
  int api_port() const;
  const config::RigdConfig& config() const { return config_; }
  api::ApiContext& api_context();
  // True while the RT loop advances (the systemd watchdog is fed only then).
  bool loop_alive();

 private:
  struct Parts;
  void start_drivers();
  void start_gpio();
  void start_loop();
  void start_services();
  void start_camera();
  void start_lab_archive();

  config::RigdConfig config_;
  std::unique_ptr<Parts> parts_;
  std::atomic<bool> stop_loop_{false};
  std::thread rt_thread_;
  std::uint64_t last_cycles_seen_ = 0;
};

std::string software_version();

}  // namespace rig::service
