#include "modbus_sim_server.hpp"

#include <arpa/inet.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/select.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "rig/proto/daq_register_map.hpp"

namespace rig::sim {
namespace reg = rig::proto::daq;

void ModbusSimServer::ModbusCloser::operator()(_modbus* ctx) const noexcept {
  modbus_close(ctx);
  modbus_free(ctx);
}
void ModbusSimServer::MappingFree::operator()(_modbus_mapping_t* mapping) const noexcept {
  modbus_mapping_free(mapping);
}

ModbusSimServer::ModbusSimServer(RigPhysics& physics, const SimServerOptions& options)
    : physics_(&physics),
      ctx_(modbus_new_tcp(options.bind.c_str(), options.port)),
      mapping_(modbus_mapping_new(0, 0, reg::kMapSize, reg::kMapSize)),
      heartbeat_(options.heartbeat_fd, options.heartbeat_ms) {
  if (!ctx_ || !mapping_)
    throw std::runtime_error("rig-sim: cannot create the Modbus server: " +
                             std::string(modbus_strerror(errno)));
  modbus_set_slave(ctx_.get(), reg::kUnitId);
  listen_fd_ = modbus_tcp_listen(ctx_.get(), 16);
  if (listen_fd_ < 0) {
    throw std::runtime_error("rig-sim: cannot listen on " + options.bind + ":" +
                             std::to_string(options.port) + ": " + modbus_strerror(errno));
  }
  sockaddr_in address{};
  socklen_t length = sizeof address;
  getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&address), &length);
  port_ = ntohs(address.sin_port);
  if (!options.rtu_device.empty()) {
    rtu_ctx_.reset(modbus_new_rtu(options.rtu_device.c_str(), options.rtu_baud, 'N', 8, 1));
    if (!rtu_ctx_ || modbus_connect(rtu_ctx_.get()) != 0) {
      throw std::runtime_error("rig-sim: cannot open the RTU line " + options.rtu_device + ": " +
                               modbus_strerror(errno));
    }
    modbus_set_slave(rtu_ctx_.get(), reg::kUnitId);
  }
  start_wall_s_ = wall_time_s();
  start_wall_s_ -= physics_->time_s();
  std::lock_guard lock(mutex_);
  refresh_registers();
}

ModbusSimServer::~ModbusSimServer() {
  if (listen_fd_ >= 0) close(listen_fd_);
}

double ModbusSimServer::wall_time_s() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

namespace {
std::int64_t steady_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// A time or duration [s] as u32 microseconds; negative (not happened yet) as 0xFFFFFFFF.
void encode_us_or_never(double seconds, std::uint16_t* words) {
  reg::encode_u32(seconds < 0 ? 0xFFFFFFFFU : static_cast<std::uint32_t>(seconds * 1e6), words);
}
}  // namespace

void ModbusSimServer::refresh_registers() {
  // The physics thread refreshes every 1 ms. A longer gap means rig-sim itself was off the
  // CPU (a busy test machine). The simulated world moves on in real time through it, as rigd's
  // does (its velocity reference, its deadlines): a world frozen for the stall would fall behind
  // rigd's reference by v x stall. But a real DAQ is never preempted and heard rigd's writes,
  // queued meanwhile: its watchdog excuses the stall, and so does the latency clock of the tests.
  const double wall_s = wall_time_s();
  constexpr double kOwnStall_s = 0.003, kTick_s = 0.001;
  if (last_refresh_wall_s_ > 0.0 && wall_s - last_refresh_wall_s_ > kOwnStall_s) {
    physics_->excuse_own_stall(wall_s - last_refresh_wall_s_ - kTick_s);
  }
  last_refresh_wall_s_ = wall_s;
  physics_->advance_to(wall_s - start_wall_s_);
  std::uint16_t* in = mapping_->tab_input_registers;
  const drivers::AnalogFrame frame = physics_->analog_frame();
  const drivers::DigitalInputs digital = physics_->digital_inputs();
  const RigTruth truth = physics_->truth();
  reg::encode_u32(frame.sequence, in + reg::input::kSequence);
  reg::encode_f32(static_cast<float>(frame.force_volts), in + reg::input::kForceVolts);
  reg::encode_f32(static_cast<float>(frame.position_volts), in + reg::input::kPositionVolts);
  reg::encode_f32(static_cast<float>(frame.iop_volts), in + reg::input::kIopVolts);
  std::uint16_t bits = 0;
  if (digital.home_limit) bits |= reg::input_bit::kHomeLimit;
  if (digital.end_limit) bits |= reg::input_bit::kEndLimit;
  if (digital.estop) bits |= reg::input_bit::kEstop;
  if (digital.drive_fault) bits |= reg::input_bit::kDriveFault;
  if (truth.watchdog_tripped) bits |= reg::input_bit::kWatchdogTripped;
  in[reg::input::kDigitalInputs] = bits;
  reg::encode_u32(static_cast<std::uint32_t>(truth.time_s * 1e6), in + reg::input::kDaqTimeUs);
  in[reg::input::kVersion] = reg::kProtocolVersion;
  reg::encode_f32(static_cast<float>(truth.carriage_mm), in + reg::sim_truth::kCarriageMm);
  reg::encode_f32(static_cast<float>(truth.force_N), in + reg::sim_truth::kForceN);
  in[reg::sim_truth::kMotorPowered] = truth.motor_powered ? 1 : 0;
  encode_us_or_never(truth.motor_off_time_s, in + reg::sim_truth::kMotorOffTimeUs);
  reg::encode_u32(static_cast<std::uint32_t>(truth.accountable_time_s * 1e6),
                  in + reg::sim_truth::kSimTimeUs);
  reg::encode_f32(static_cast<float>(truth.tip_depth_mm), in + reg::sim_truth::kTipDepthMm);
  encode_us_or_never(truth.motor_off_silence_s, in + reg::sim_truth::kMotorOffSilenceUs);
}

namespace {
// A panel float the test wrote; NaN or infinity (garbage written) means "no injection".
double finite_or_zero(float value) {
  return std::isfinite(value) ? value : 0.0;
}
}  // namespace

void ModbusSimServer::apply_writes() {
  const std::uint16_t* h = mapping_->tab_registers;
  InjectedFaults& faults = physics_->faults();
  faults.estop_pressed = h[reg::sim_panel::kEstopButton] != 0;
  faults.stuck_force = h[reg::sim_panel::kStuckForce] != 0;
  faults.extra_force_N = finite_or_zero(reg::decode_f32(h + reg::sim_panel::kExtraForceN));
  faults.end_limit_forced = h[reg::sim_panel::kEndLimitForced] != 0;
  faults.home_limit_forced = h[reg::sim_panel::kHomeLimitForced] != 0;
  faults.drive_fault = h[reg::sim_panel::kDriveFault] != 0;
  faults.carriage_jammed = h[reg::sim_panel::kCarriageJammed] != 0;
  faults.position_offset_mm =
      finite_or_zero(reg::decode_f32(h + reg::sim_panel::kPositionOffsetMm));
  // Clamped to 0..1 by the IOP line: a fraction of the pressure, never more than all of it.
  faults.iop_leak_fraction = finite_or_zero(reg::decode_f32(h + reg::sim_panel::kIopLeak));
  faults.home_switch_broken = h[reg::sim_panel::kHomeSwitchBroken] != 0;
  faults.writes_rejected = h[reg::sim_panel::kRejectWrites] != 0;
  if (new_nonzero(h[reg::sim_panel::kNewEye], last_new_eye_)) physics_->mount_new_eye(2.0);
  if (new_nonzero(h[reg::sim_panel::kRestartDaq], last_restart_)) physics_->restart_daq();
  if (new_nonzero(h[reg::sim_panel::kTripWatchdog], last_trip_)) physics_->trip_watchdog();
}

// One-shot panel registers act once per new non-zero value written.
bool ModbusSimServer::new_nonzero(std::uint16_t value, std::uint16_t& last) {
  const bool act = value != last && value != 0;
  last = value;
  return act;
}

void ModbusSimServer::drop_all(std::vector<int>& clients) {
  for (const int fd : clients) close(fd);
  clients.clear();
}

void ModbusSimServer::accept_client(std::vector<int>& clients) {
  const int fd = accept(listen_fd_, nullptr, nullptr);
  if (fd < 0) return;
  // Replies must leave at once: without TCP_NODELAY, Nagle + delayed ACK hold the second
  // reply of a cycle (read, then write) for up to 40 ms.
  const int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  bool dropping = false;
  {
    std::lock_guard lock(mutex_);
    dropping = mapping_->tab_registers[reg::sim_panel::kLinkDrop] != 0;
  }
  if (dropping) {
    close(fd);  // the link is "cut": connections die at once
    return;
  }
  clients.push_back(fd);
}

ModbusSimServer::Served ModbusSimServer::serve_request(_modbus* ctx) {
  std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];  // larger than any RTU frame (256 B)
  const int length = modbus_receive(ctx, query);
  if (length < 0) return Served::kPeerGone;
  if (length == 0) return Served::kOk;  // addressed to another unit
  std::uint16_t late_us = 0;
  bool garbage = false;
  {
    std::lock_guard lock(mutex_);
    if (mapping_->tab_registers[reg::sim_panel::kLinkDrop] != 0) return Served::kLinkCut;
    late_us = mapping_->tab_registers[reg::sim_panel::kLateReplyUs];
    garbage = mapping_->tab_registers[reg::sim_panel::kGarbageReplies] != 0;
  }
  if (late_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(late_us));
  std::lock_guard lock(mutex_);
  refresh_registers();
  const int header = modbus_get_header_length(ctx);
  const int function = query[header];
  const int address = (query[header + 1] << 8) | query[header + 2];
  if (function == MODBUS_FC_READ_INPUT_REGISTERS) heartbeat_.note_read_request(steady_ns());
  if (garbage && function == MODBUS_FC_READ_INPUT_REGISTERS) {
    std::fill_n(mapping_->tab_input_registers, reg::input::kCount, std::uint16_t{0xFFFF});
  }
  const bool write = function == MODBUS_FC_WRITE_SINGLE_REGISTER ||
                     function == MODBUS_FC_WRITE_MULTIPLE_REGISTERS ||
                     function == MODBUS_FC_WRITE_AND_READ_REGISTERS;
  if (write && address < reg::holding::kCount && physics_->faults().writes_rejected) {
    // The DAQ answers but refuses its outputs (exception 4, server device failure).
    const int refused =
        modbus_reply_exception(ctx, query, MODBUS_EXCEPTION_SLAVE_OR_SERVER_FAILURE);
    return refused < 0 ? Served::kPeerGone : Served::kOk;
  }
  const int rc = modbus_reply(ctx, query, length, mapping_.get());
  if (write) {
    apply_writes();
    if (address < reg::holding::kCount) {
      const std::uint16_t* h = mapping_->tab_registers;
      drivers::DriveCommand drive;
      drivers::DigitalOutputs digital;
      drive.motor_enable = (h[reg::holding::kDigitalOutputs] & reg::output_bit::kMotorEnable) != 0;
      digital.motor_enable = drive.motor_enable;
      digital.camera_trigger =
          (h[reg::holding::kDigitalOutputs] & reg::output_bit::kCameraTrigger) != 0;
      drive.motor_volts = reg::decode_f32(h + reg::holding::kMotorVolts);
      drive.pump_command = reg::decode_f32(h + reg::holding::kPumpCommand);
      if (!std::isfinite(drive.motor_volts) || !std::isfinite(drive.pump_command)) drive = {};
      physics_->set_watchdog_ms(h[reg::holding::kWatchdogMs]);
      physics_->write_outputs(drive, digital);
    }
  }
  return rc < 0 ? Served::kPeerGone : Served::kOk;
}

void ModbusSimServer::serve_client(int fd, std::vector<int>& clients) {
  modbus_set_socket(ctx_.get(), fd);
  const std::int64_t readable_ns = steady_ns();
  const Served served = serve_request(ctx_.get());
  const std::int64_t replied_ns = steady_ns();
  reply_time_.record(replied_ns - readable_ns);
  if (last_reply_ns_ != 0) reply_gap_.record(replied_ns - last_reply_ns_);
  last_reply_ns_ = replied_ns;
  if (served == Served::kLinkCut) return drop_all(clients);
  if (served == Served::kPeerGone) {
    close(fd);
    clients.erase(std::remove(clients.begin(), clients.end(), fd), clients.end());
  }
}

void ModbusSimServer::serve_rtu() {
  // A serial line has no connection to drop: a cut link is a DAQ that stays silent, and a
  // broken frame (CRC, gap) is flushed so the next request starts clean.
  if (serve_request(rtu_ctx_.get()) == Served::kPeerGone) modbus_flush(rtu_ctx_.get());
}

void ModbusSimServer::physics_thread(const std::atomic<bool>& stop) {
  // The DAQ's own conversion clock: 1 kHz on absolute deadlines, so physics and the DAQ
  // watchdog move on without requests and a reply never has more than ~1 ms to catch up.
  double drop_until_s = -1.0;
  auto next = std::chrono::steady_clock::now();
  while (!stop.load()) {
    next += std::chrono::milliseconds(1);
    const auto woke = std::chrono::steady_clock::now();
    if (next < woke) next = woke;  // after a stall: carry on from now, do not burst
    std::this_thread::sleep_until(next);
    physics_lateness_.record(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                 std::chrono::steady_clock::now() - next)
                                 .count());
    heartbeat_.tick(steady_ns());
    std::lock_guard lock(mutex_);
    refresh_registers();
    std::uint16_t& drop = mapping_->tab_registers[reg::sim_panel::kLinkDrop];
    if (drop == 0) {
      drop_until_s = -1.0;
    } else if (drop != 0xFFFF) {  // value in units of 10 ms; 0xFFFF = until cleared by restart
      const double now = wall_time_s();
      if (drop_until_s < 0.0) drop_until_s = now + drop * 0.01;
      if (now >= drop_until_s) drop = 0;
    }
  }
}

void ModbusSimServer::run(const std::atomic<bool>& stop) {
  std::thread physics([this, &stop] { physics_thread(stop); });
  std::vector<int> clients;
  while (!stop.load()) {
    fd_set read_set;
    FD_ZERO(&read_set);
    FD_SET(listen_fd_, &read_set);
    int max_fd = listen_fd_;
    const int rtu_fd = rtu_ctx_ ? modbus_get_socket(rtu_ctx_.get()) : -1;
    if (rtu_fd >= 0) {
      FD_SET(rtu_fd, &read_set);
      max_fd = std::max(max_fd, rtu_fd);
    }
    for (const int fd : clients) {
      FD_SET(fd, &read_set);
      max_fd = std::max(max_fd, fd);
    }
    timeval timeout{0, 100000};
    const int ready = select(max_fd + 1, &read_set, nullptr, nullptr, &timeout);
    if (ready <= 0) continue;
    if (FD_ISSET(listen_fd_, &read_set)) accept_client(clients);
    if (rtu_fd >= 0 && FD_ISSET(rtu_fd, &read_set)) serve_rtu();
    const std::vector<int> snapshot = clients;
    for (const int fd : snapshot) {
      if (FD_ISSET(fd, &read_set) && std::find(clients.begin(), clients.end(), fd) != clients.end())
        serve_client(fd, clients);
    }
  }
  drop_all(clients);
  physics.join();
}

}  // namespace rig::sim
