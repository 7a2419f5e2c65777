#pragma once
// rig-sim's Modbus TCP (and optionally RTU) server: the simulated rig's DAQ behind the real
// register map (proto/include/rig/proto/daq_register_map.hpp). Any Modbus client can talk to it:
// rigd, mbpoll, a lab's own tools. Physics advances on every request (a DAQ converts continuously)
// and in the background, so the DAQ watchdog runs without requests too.
#include <atomic>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "heartbeat_writer.hpp"
#include "latency_tally.hpp"
#include "rig/sim/rig_physics.hpp"

// The C library's own struct tags, declared here so the header need not include it.
// NOLINTBEGIN(bugprone-reserved-identifier)
struct _modbus;
struct _modbus_mapping_t;
// NOLINTEND(bugprone-reserved-identifier)

namespace rig::sim {

struct SimServerOptions {
  std::string bind = "127.0.0.1";
  int port = 1502;  // 0 = any free port
  // Also serve Modbus RTU on this serial line (a real port, or a pty from socat), with the
  // same registers: the DAQ on RTU while tests and mbpoll keep the TCP panel.
  std::string rtu_device;
  int rtu_baud = 115200;
  // Heartbeat lines (heartbeat_writer.hpp) on this open descriptor every heartbeat_ms [ms];
  // -1 = none (the default).
  int heartbeat_fd = -1;
  int heartbeat_ms = 5;
};

class ModbusSimServer {
 public:
  ModbusSimServer(RigPhysics& physics, const SimServerOptions& options);  // binds; throws
  ~ModbusSimServer();
  ModbusSimServer(const ModbusSimServer&) = delete;
  ModbusSimServer& operator=(const ModbusSimServer&) = delete;

  int port() const { return port_; }
  void run(const std::atomic<bool>& stop);  // serves until stop is set
  // Where the time went (printed by rig-sim at exit): a request's time from readable socket
  // to reply sent, the gap between two replies on one client, the physics clock's lateness.
  const LatencyTally& reply_time() const { return reply_time_; }
  const LatencyTally& reply_gap() const { return reply_gap_; }
  const LatencyTally& physics_lateness() const { return physics_lateness_; }
  const HeartbeatWriter& heartbeat() const { return heartbeat_; }

 private:
  struct ModbusCloser {
    void operator()(_modbus* ctx) const noexcept;
  };
  struct MappingFree {
    void operator()(_modbus_mapping_t* mapping) const noexcept;
  };

  void physics_thread(const std::atomic<bool>& stop);
  double wall_time_s() const;
  void refresh_registers();  // physics -> input registers (mutex held)
  void apply_writes();       // holding registers -> physics and faults (mutex held)
  static bool new_nonzero(std::uint16_t value, std::uint16_t& last);
  enum class Served { kOk, kPeerGone, kLinkCut };
  Served serve_request(_modbus* ctx);  // one request on a TCP client or the RTU line
  void serve_client(int fd, std::vector<int>& clients);
  void serve_rtu();
  void accept_client(std::vector<int>& clients);
  void drop_all(std::vector<int>& clients);

  RigPhysics* physics_;
  std::unique_ptr<_modbus, ModbusCloser> ctx_;
  std::unique_ptr<_modbus, ModbusCloser> rtu_ctx_;  // null: TCP only
  std::unique_ptr<_modbus_mapping_t, MappingFree> mapping_;
  std::mutex mutex_;  // guards physics_ and mapping_
  int listen_fd_ = -1;
  int port_ = 0;
  double start_wall_s_ = 0.0;
  std::uint16_t last_new_eye_ = 0;
  std::uint16_t last_restart_ = 0;  // kRestartDaq, kTripWatchdog: act on each new value
  std::uint16_t last_trip_ = 0;
  double last_refresh_wall_s_ = 0.0;
  LatencyTally reply_time_;
  LatencyTally reply_gap_;
  LatencyTally physics_lateness_;
  HeartbeatWriter heartbeat_;       // written by the physics thread, fed by the server thread
  std::int64_t last_reply_ns_ = 0;  // steady clock, server thread only
};

}  // namespace rig::sim
