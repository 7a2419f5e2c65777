#pragma once
// rigd's configuration (TOML). Every key is declared once in config_schema.cpp with its
// type, range and documentation; an unknown key or a bad value is an error naming the
// file, line and key. Loop settings are the RT loop's own struct.
#include <cstdint>
#include <string>
#include <vector>

#include "lab_archive_section.hpp"
#include "loop_settings.hpp"
#include "modbus/modbus_daq.hpp"

namespace rig::config {

struct LoopThread {
  int priority = 80;            // SCHED_FIFO priority, 0 = do not ask for real-time
  int cpu = -1;                 // pin the RT thread to this CPU, -1 = no pinning
  bool lock_memory = true;      // mlockall(MCL_CURRENT | MCL_FUTURE)
  int cpu_wake_latency_us = 0;  // PM QoS while the loop runs: idle CPUs poll (0), -1 = no request
};

struct DaqSection {
  std::string kind = "modbus";  // "modbus" (TCP or RTU), "usb"
  drivers::ModbusDaqSettings modbus;
  int usb_vendor_id = 0x1d6b;
  int usb_product_id = 0x0104;
};

struct GpioSection {
  bool enabled = false;
  std::string chip = "gpiochip0";
  int home_line = 0;
  int end_line = 1;
  int estop_line = 2;
  int motor_enable_line = 3;
  int camera_trigger_line = 4;
  bool estop_active_low = true;  // e-stop loops are normally closed
  int debounce_us = 2000;
};

struct CameraSection {
  std::string kind = "none";  // none, sim, aravis, v4l2
  std::string id;             // Aravis id or IP address, or /dev/videoN
  int width = 640;
  int height = 480;
  double frame_rate_hz = 30.0;
  double exposure_us = 2000.0;
  bool hardware_trigger = false;
  int packet_size = 1400;
  std::string frames_dir;     // per-run frame files; empty = <archive dir>/frames
  bool record_frames = true;  // every frame of a run to its frame file + archive index
  int lost_after_ms = 1000;   // no frame this long while recording faults the run (0 = never)
};

struct ArchiveSection {
  std::string path = "/var/lib/rigd/archive.sqlite";
  int flush_interval_ms = 50;  // commit period: a crash loses at most ~2x this
  // SCHED_FIFO priority of the recorder thread, below the loop's: its commits come on time
  // while the API and other processes wait (it sleeps between commits and blocks in fsync,
  // never spins). 0 = normal scheduling.
  int recorder_priority = 60;
};

struct ApiSection {
  std::string bind = "127.0.0.1";
  int port = 8080;
  std::string token_file;  // required for any non-loopback bind
  std::string web_root = "/usr/share/rigd/web";
  int max_body_bytes = 65536;
  int max_clients = 64;              // general connections (HTTP and WebSocket) in all
  int max_clients_per_address = 32;  // of those, from one peer address (capped at max_clients)
  std::string allowed_origins;       // comma-separated page origins besides rigd's own (CSRF guard)
};

struct StreamSection {
  int batch_ms = 50;         // WebSocket and UDP batch period
  bool udp_enabled = false;  // PlotJuggler UDP JSON
  std::string udp_host = "127.0.0.1";
  int udp_port = 9870;
  int camera_max_hz = 15;  // camera frames to the page
};

struct ModelSection {
  std::string file = "/usr/share/rigd/models/paper-interpreted.toml";
};

struct RigdConfig {
  rt::LoopSettings loop;
  LoopThread thread;
  DaqSection daq;
  GpioSection gpio;
  CameraSection camera;
  ArchiveSection archive;
  ApiSection api;
  StreamSection stream;
  ModelSection model;
  LabArchiveSection lab_archive;
  std::string source_path;  // file it was read from
  std::string hash;         // FNV-1a of the file and the overrides, hex
};

// Reads and validates a config file, then applies "key=value" overrides (TOML values).
// Throws ConfigError whose message names the file (or --set), line and key.
RigdConfig load_rigd_config(const std::string& path,
                            const std::vector<std::string>& overrides = {});

// Documentation of every key (for `rigd --print-config-keys` and docs/config.md).
std::string describe_config_keys();

}  // namespace rig::config
