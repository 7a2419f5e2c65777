#include "config_schema.hpp"

#include <limits>

namespace rig::config {
namespace {

using Type = ConfigField::Type;

template <typename Access>
ConfigField number(std::string key, double min, double max, std::string doc, Access access) {
  return {std::move(key),
          Type::kNumber,
          min,
          max,
          {},
          std::move(doc),
          [access](RigdConfig& c, const ConfigValue& v) { access(c) = std::get<double>(v); }};
}

template <typename Access>
ConfigField integer(std::string key, double min, double max, std::string doc, Access access) {
  return {std::move(key),
          Type::kInteger,
          min,
          max,
          {},
          std::move(doc),
          [access](RigdConfig& c, const ConfigValue& v) {
            access(c) = static_cast<std::remove_reference_t<decltype(access(c))>>(
                std::get<std::int64_t>(v));
          }};
}

template <typename Access>
ConfigField boolean(std::string key, std::string doc, Access access) {
  return {std::move(key),
          Type::kBoolean,
          0,
          0,
          {},
          std::move(doc),
          [access](RigdConfig& c, const ConfigValue& v) { access(c) = std::get<bool>(v); }};
}

template <typename Access>
ConfigField path(std::string key, std::string doc, Access access) {
  ConfigField field{
      std::move(key),
      Type::kString,
      0,
      0,
      {},
      std::move(doc),
      [access](RigdConfig& c, const ConfigValue& v) { access(c) = std::get<std::string>(v); }};
  field.is_path = true;
  return field;
}

template <typename Access>
ConfigField text(std::string key, std::vector<std::string> choices, std::string doc,
                 Access access) {
  return {std::move(key),
          Type::kString,
          0,
          0,
          std::move(choices),
          std::move(doc),
          [access](RigdConfig& c, const ConfigValue& v) { access(c) = std::get<std::string>(v); }};
}

// A member path (loop.rate_hz), which no parentheses may enclose.
// NOLINTBEGIN(bugprone-macro-parentheses)
#define RIG_AT(member)          \
  [](RigdConfig & c) -> auto& { \
    return c.member;            \
  }
// NOLINTEND(bugprone-macro-parentheses)

void add_loop_fields(std::vector<ConfigField>& f) {
  f.push_back(
      number("loop.rate_hz", 1000, 10000, "control and sampling rate [Hz]", RIG_AT(loop.rate_hz)));
  f.push_back(integer("loop.priority", 0, 99, "SCHED_FIFO priority of the RT thread, 0 = none",
                      RIG_AT(thread.priority)));
  f.push_back(
      integer("loop.cpu", -1, 1023, "CPU to pin the RT thread to, -1 = any", RIG_AT(thread.cpu)));
  f.push_back(
      boolean("loop.lock_memory", "mlockall before the loop starts", RIG_AT(thread.lock_memory)));
  f.push_back(
      integer("loop.cpu_wake_latency_us", -1, 100000,
              "longest CPU wake-up from idle while the loop runs (PM QoS), -1 = no request [us]",
              RIG_AT(thread.cpu_wake_latency_us)));
  for (const char* channel : {"force", "position", "iop"}) {
    const std::string base = std::string("calibration.") + channel;
    auto pick = [c = std::string(channel)](RigdConfig& cfg) -> rt::LinearCalibration& {
      return c == "force"
                 ? cfg.loop.calibration.force
                 : (c == "position" ? cfg.loop.calibration.position : cfg.loop.calibration.iop);
    };
    f.push_back(number(base + ".offset_V", -12, 12, "DAQ volts at zero",
                       [pick](RigdConfig& c) -> double& { return pick(c).offset_volts; }));
    f.push_back(number(base + ".units_per_V", -1e6, 1e6,
                       "engineering units per volt (N/V, mm/V, mmHg/V)",
                       [pick](RigdConfig& c) -> double& { return pick(c).units_per_volt; }));
  }
}

void add_motion_fields(std::vector<ConfigField>& f) {
  f.push_back(number("motion.park_mm", -10, 100, "carriage position where runs start and end [mm]",
                     RIG_AT(loop.motion.park_mm)));
  f.push_back(number("motion.surface_mm", -10, 100,
                     "carriage position where the tip touches the cornea [mm]",
                     RIG_AT(loop.motion.surface_mm)));
  f.push_back(number("motion.home_switch_mm", -10, 100,
                     "carriage position where the home switch closes [mm]",
                     RIG_AT(loop.motion.home_switch_mm)));
  f.push_back(number("motion.homing_velocity_mm_s", 0.1, 10, "homing speed [mm/s]",
                     RIG_AT(loop.motion.homing_velocity_mm_s)));
  f.push_back(number("motion.retract_velocity_mm_s", 0.1, 10, "retraction speed [mm/s]",
                     RIG_AT(loop.motion.retract_velocity_mm_s)));
  f.push_back(number("motion.min_velocity_mm_s", 0.01, 10,
                     "slowest cutting velocity allowed [mm/s]",
                     RIG_AT(loop.motion.min_velocity_mm_s)));
  f.push_back(number("motion.max_velocity_mm_s", 0.01, 10,
                     "fastest cutting velocity allowed [mm/s]",
                     RIG_AT(loop.motion.max_velocity_mm_s)));
  f.push_back(number("motion.max_depth_mm", 0.1, 50, "deepest insertion allowed [mm]",
                     RIG_AT(loop.motion.max_depth_mm)));
  f.push_back(number("motion.soft_min_mm", -10, 100, "soft travel limit, home side [mm]",
                     RIG_AT(loop.motion.soft_min_mm)));
  f.push_back(number("motion.soft_max_mm", -10, 100, "soft travel limit, eye side [mm]",
                     RIG_AT(loop.motion.soft_max_mm)));
  f.push_back(number("motion.max_homing_travel_mm", 1, 200,
                     "homing fails after this travel without the switch [mm]",
                     RIG_AT(loop.motion.max_homing_travel_mm)));
  f.push_back(number("motion.park_tolerance_mm", 0.01, 5, "how close to park a run may start [mm]",
                     RIG_AT(loop.motion.park_tolerance_mm)));
  f.push_back(number("control.feedforward_V_per_mm_s", 0, 100, "motor volts per mm/s (back-EMF)",
                     RIG_AT(loop.gains.feedforward_V_per_mm_s)));
  f.push_back(number("control.kp_V_per_mm", 0, 10000, "proportional gain on position error [V/mm]",
                     RIG_AT(loop.gains.kp_V_per_mm)));
  f.push_back(number("control.ki_V_per_mm_s", 0, 100000, "integral gain [V/(mm s)]",
                     RIG_AT(loop.gains.ki_V_per_mm_s)));
  f.push_back(number("control.max_volts", 0.1, 48, "motor voltage limit [V]",
                     RIG_AT(loop.gains.max_volts)));
  f.push_back(number("control.velocity_filter_s", 0.0001, 1,
                     "velocity estimate low-pass time constant [s]",
                     RIG_AT(loop.gains.velocity_filter_s)));
}

void add_iop_and_safety_fields(std::vector<ConfigField>& f) {
  f.push_back(number("iop.pump_full_scale_mmHg", 1, 200,
                     "IOP at full pump command (feed-forward) [mmHg]",
                     RIG_AT(loop.iop.pump_full_scale_mmHg)));
  f.push_back(number("iop.kp_per_mmHg", 0, 10, "pump command per mmHg of error",
                     RIG_AT(loop.iop.kp_per_mmHg)));
  f.push_back(number("iop.ki_per_mmHg_s", 0, 10, "pump integral gain [1/(mmHg s)]",
                     RIG_AT(loop.iop.ki_per_mmHg_s)));
  f.push_back(number("iop.settle_band_mmHg", 0.01, 10, "settled when within this band [mmHg] ...",
                     RIG_AT(loop.iop.settle_band_mmHg)));
  f.push_back(
      number("iop.settle_time_s", 0, 60, "... for this long [s]", RIG_AT(loop.iop.settle_time_s)));
  f.push_back(number("iop.settle_timeout_s", 1, 600, "fault if not settled after [s]",
                     RIG_AT(loop.iop.settle_timeout_s)));
  f.push_back(number("iop.min_mmHg", 0, 100, "lowest IOP a run may ask for [mmHg]",
                     RIG_AT(loop.iop.min_mmHg)));
  f.push_back(number("iop.max_mmHg", 0, 100, "highest IOP a run may ask for [mmHg]",
                     RIG_AT(loop.iop.max_mmHg)));
  f.push_back(number("iop.fault_band_mmHg", 0.1, 100,
                     "fault if IOP leaves target +- band during a cut [mmHg]",
                     RIG_AT(loop.iop.fault_band_mmHg)));
  f.push_back(number("iop.fault_after_ms", 1, 5000,
                     "... for this long [ms] (a pump step is not a leak)",
                     RIG_AT(loop.iop.fault_after_ms)));
  f.push_back(number("safety.force_limit_N", 0.01, 100, "load-cell protection [N]",
                     RIG_AT(loop.safety.force_limit_N)));
  f.push_back(number("safety.link_lost_after_ms", 0.5, 1000,
                     "time without a valid DAQ reply (on-time cycles) before link loss [ms]",
                     RIG_AT(loop.safety.link_lost_after_ms)));
  f.push_back(integer("safety.overrun_storm_missed_cycles", 1, 2000, "deadlines missed ...",
                      RIG_AT(loop.safety.overrun_storm_missed_cycles)));
  f.push_back(integer("safety.overrun_storm_window_cycles", 1, 2000,
                      "... within this many deadlines fault the loop (overrun storm)",
                      RIG_AT(loop.safety.overrun_storm_window_cycles)));
  f.push_back(number("safety.max_following_error_mm", 0.01, 50,
                     "fault when the carriage lags its reference by more [mm]",
                     RIG_AT(loop.safety.max_following_error_mm)));
  f.push_back(integer("safety.stuck_force_cycles", 2, 100000,
                      "identical force readings while cutting = stuck sensor",
                      RIG_AT(loop.safety.stuck_force_cycles)));
  f.push_back(integer("safety.max_failed_writes", 1, 1000,
                      "output writes lost or garbled in a row (reads answered) before the run "
                      "faults; a refused write faults at once",
                      RIG_AT(loop.safety.max_failed_writes)));
  f.push_back(integer("safety.tare_cycles", 1, 100000, "cycles averaged by tare",
                      RIG_AT(loop.safety.tare_cycles)));
}

void add_daq_fields(std::vector<ConfigField>& f) {
  f.push_back(text("daq.kind", {"modbus", "usb"}, "DAQ type", RIG_AT(daq.kind)));
  f.push_back(
      text("daq.transport", {"tcp", "rtu"}, "Modbus transport", RIG_AT(daq.modbus.transport)));
  f.push_back(text("daq.host", {}, "Modbus TCP host", RIG_AT(daq.modbus.host)));
  f.push_back(integer("daq.port", 1, 65535, "Modbus TCP port", RIG_AT(daq.modbus.port)));
  f.push_back(
      text("daq.serial_device", {}, "Modbus RTU serial device", RIG_AT(daq.modbus.serial_device)));
  f.push_back(integer("daq.baud", 1200, 4000000, "Modbus RTU baud rate", RIG_AT(daq.modbus.baud)));
  f.push_back({"daq.parity",
               Type::kString,
               0,
               0,
               {"N", "E", "O"},
               "Modbus RTU parity",
               [](RigdConfig& c, const ConfigValue& v) {
                 c.daq.modbus.parity = std::get<std::string>(v)[0];
               }});
  f.push_back(integer("daq.data_bits", 7, 8, "Modbus RTU data bits", RIG_AT(daq.modbus.data_bits)));
  f.push_back(integer("daq.stop_bits", 1, 2, "Modbus RTU stop bits", RIG_AT(daq.modbus.stop_bits)));
  f.push_back(integer("daq.unit_id", 0, 247, "Modbus unit id", RIG_AT(daq.modbus.unit_id)));
  f.push_back(integer("daq.response_timeout_us", 50, 1000000,
                      "reply time-out; keep below one loop period [us]",
                      RIG_AT(daq.modbus.response_timeout_us)));
  f.push_back(integer("daq.watchdog_ms", 1, 1000,
                      "DAQ turns its outputs off after this silence [ms] (never off: it is the "
                      "last line of defence when rigd dies)",
                      RIG_AT(daq.modbus.watchdog_ms)));
  f.push_back(
      integer("daq.usb_vendor_id", 0, 65535, "USB DAQ vendor id", RIG_AT(daq.usb_vendor_id)));
  f.push_back(
      integer("daq.usb_product_id", 0, 65535, "USB DAQ product id", RIG_AT(daq.usb_product_id)));
}

void add_io_fields(std::vector<ConfigField>& f) {
  f.push_back(boolean("gpio.enabled", "use GPIO lines for switches, e-stop, enable, trigger",
                      RIG_AT(gpio.enabled)));
  f.push_back(text("gpio.chip", {}, "GPIO chip (name or /dev path)", RIG_AT(gpio.chip)));
  f.push_back(integer("gpio.home_line", 0, 1023, "home switch line", RIG_AT(gpio.home_line)));
  f.push_back(integer("gpio.end_line", 0, 1023, "end switch line", RIG_AT(gpio.end_line)));
  f.push_back(integer("gpio.estop_line", 0, 1023, "e-stop line", RIG_AT(gpio.estop_line)));
  f.push_back(integer("gpio.motor_enable_line", 0, 1023, "motor enable output line",
                      RIG_AT(gpio.motor_enable_line)));
  f.push_back(integer("gpio.camera_trigger_line", 0, 1023, "camera trigger output line",
                      RIG_AT(gpio.camera_trigger_line)));
  f.push_back(boolean("gpio.estop_active_low", "e-stop reads 0 when pressed (normally closed loop)",
                      RIG_AT(gpio.estop_active_low)));
  f.push_back(
      integer("gpio.debounce_us", 0, 1000000, "switch debounce [us]", RIG_AT(gpio.debounce_us)));
  f.push_back(text("camera.kind", {"none", "sim", "aravis", "v4l2"},
                   "camera driver (sim: rendered from the rig's state)", RIG_AT(camera.kind)));
  f.push_back(text("camera.id", {}, "Aravis id or IP, or V4L2 device", RIG_AT(camera.id)));
  f.push_back(integer("camera.width", 16, 8192, "image width [px]", RIG_AT(camera.width)));
  f.push_back(integer("camera.height", 16, 8192, "image height [px]", RIG_AT(camera.height)));
  f.push_back(
      number("camera.frame_rate_hz", 0.1, 10000, "frame rate [Hz]", RIG_AT(camera.frame_rate_hz)));
  f.push_back(number("camera.exposure_us", 1, 1e7, "exposure [us]", RIG_AT(camera.exposure_us)));
  f.push_back(boolean("camera.hardware_trigger", "expose on the GPIO trigger line",
                      RIG_AT(camera.hardware_trigger)));
  f.push_back(
      integer("camera.packet_size", 576, 9000, "GigE packet size [B]", RIG_AT(camera.packet_size)));
  f.push_back(path("camera.frames_dir", "where per-run frame files go", RIG_AT(camera.frames_dir)));
  f.push_back(integer("camera.lost_after_ms", 0, 60000,
                      "no frame this long while recording faults the run, 0 = never [ms]",
                      RIG_AT(camera.lost_after_ms)));
  f.push_back(boolean("camera.record_frames",
                      "record every frame of a run (frame file + archive index)",
                      RIG_AT(camera.record_frames)));
}

void add_service_fields(std::vector<ConfigField>& f) {
  f.push_back(path("archive.path", "SQLite archive file", RIG_AT(archive.path)));
  f.push_back(integer("archive.recorder_priority", 0, 98,
                      "SCHED_FIFO priority of the recorder (below loop.priority): commits on time "
                      "on a busy machine, 0 = normal scheduling",
                      RIG_AT(archive.recorder_priority)));
  f.push_back(integer("archive.flush_interval_ms", 5, 50,
                      "commit period [ms] (crash loses at most about twice this)",
                      RIG_AT(archive.flush_interval_ms)));
  f.push_back(text("api.bind", {}, "address the API binds to (non-loopback needs a token)",
                   RIG_AT(api.bind)));
  f.push_back(integer("api.port", 0, 65535, "API port, 0 = any free port", RIG_AT(api.port)));
  f.push_back(
      path("api.token_file", "file holding the API token (mode 0600)", RIG_AT(api.token_file)));
  f.push_back(path("api.web_root", "directory of the overlay page", RIG_AT(api.web_root)));
  f.push_back(integer("api.max_body_bytes", 256, 16777216, "largest request body [B]",
                      RIG_AT(api.max_body_bytes)));
  f.push_back(text("api.allowed_origins", {},
                   "comma-separated origins (http[s]://host[:port]) of pages that may command rigd "
                   "besides its own",
                   RIG_AT(api.allowed_origins)));
  f.push_back(integer("api.max_clients", 1, 1024, "concurrent connections (HTTP and WebSocket)",
                      RIG_AT(api.max_clients)));
  f.push_back(
      integer("api.max_clients_per_address", 1, 1024,
              "concurrent connections from one peer address (at most api.max_clients count)",
              RIG_AT(api.max_clients_per_address)));
  f.push_back(integer("stream.batch_ms", 5, 1000, "live stream batch period [ms]",
                      RIG_AT(stream.batch_ms)));
  f.push_back(
      boolean("stream.udp_enabled", "PlotJuggler UDP JSON stream", RIG_AT(stream.udp_enabled)));
  f.push_back(text("stream.udp_host", {}, "UDP destination host", RIG_AT(stream.udp_host)));
  f.push_back(
      integer("stream.udp_port", 1, 65535, "UDP destination port", RIG_AT(stream.udp_port)));
  f.push_back(integer("stream.camera_max_hz", 1, 30, "camera frames to the page per second",
                      RIG_AT(stream.camera_max_hz)));
  f.push_back(path("model.file", "force model file for the live overlay", RIG_AT(model.file)));
}

}  // namespace

const std::vector<ConfigField>& config_fields() {
  static const std::vector<ConfigField> kFields = [] {
    std::vector<ConfigField> f;
    add_loop_fields(f);
    add_motion_fields(f);
    add_iop_and_safety_fields(f);
    add_daq_fields(f);
    add_io_fields(f);
    add_service_fields(f);
    add_lab_archive_fields(f);
    return f;
  }();
  return kFields;
}

}  // namespace rig::config
