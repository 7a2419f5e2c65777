#include "rigd_app.hpp"

#include <spdlog/spdlog.h>

#include <unistd.h>

#include <filesystem>

#include "api_server.hpp"
#include "camera/aravis_camera.hpp"
#include "camera/v4l2_camera.hpp"
#include "camera_service.hpp"
#include "clock/cpu_wake_latency_request.hpp"
#include "clock/monotonic_clock.hpp"
#include "control_loop.hpp"
#include "force_model.hpp"
#include "gpio/gpio_digital_io.hpp"
#include "haptic_service.hpp"
#include "lab_replicator.hpp"
#include "lab_worker.hpp"
#include "modbus/modbus_daq.hpp"
#include "model_lint.hpp"
#include "recorder.hpp"
#include "rt_thread.hpp"
#include "sim_camera.hpp"
#include "stream_hub.hpp"
#include "udp_publisher.hpp"
#include "usb/usb_daq.hpp"

namespace rig::service {

std::string software_version() {
  return RIGD_VERSION;
}

namespace {
// This machine's name: a page reached as http://<hostname>:8080/ is rigd's own.
std::string machine_host_name() {
  char name[256] = {};
  if (gethostname(name, sizeof name - 1) != 0) return {};
  return name;
}
}  // namespace

struct RigdApp::Parts {
  std::unique_ptr<drivers::ModbusDaq> daq;
  std::unique_ptr<drivers::UsbDaq> usb_daq;
  std::unique_ptr<drivers::GpioDigitalIo> gpio;
  drivers::AnalogInput* analog = nullptr;
  drivers::DigitalIo* digital = nullptr;
  drivers::ActuatorDrive* drive = nullptr;
  drivers::MonotonicClock clock;
  std::unique_ptr<rt::LoopChannels> channels;
  std::unique_ptr<rt::ControlLoop> loop;
  std::unique_ptr<Recorder> recorder;
  std::unique_ptr<StreamHub> hub;
  std::unique_ptr<UdpPublisher> udp;
  std::unique_ptr<CameraService> camera;
  std::unique_ptr<LabWorker> lab;
  std::unique_ptr<HapticService> haptic;
  std::unique_ptr<lab_archive::LabReplicator>
      lab_replicator;  // [lab_archive] on: store and forward
  api::ApiContext api_context;
  std::unique_ptr<api::ApiServer> api;
  RtThreadReport rt_report;
  std::unique_ptr<drivers::CpuWakeLatencyRequest> wake_latency;
};

RigdApp::RigdApp(config::RigdConfig config)
    : config_(std::move(config)), parts_(std::make_unique<Parts>()) {}

RigdApp::~RigdApp() {
  shutdown();
}

api::ApiContext& RigdApp::api_context() {
  return parts_->api_context;
}

int RigdApp::api_port() const {
  return parts_->api ? parts_->api->port() : 0;
}

void RigdApp::start_drivers() {
  if (config_.daq.kind == "usb") {
    drivers::UsbDaqSettings usb;
    usb.vendor_id = config_.daq.usb_vendor_id;
    usb.product_id = config_.daq.usb_product_id;
    usb.watchdog_ms = config_.daq.modbus.watchdog_ms;
    parts_->usb_daq = std::make_unique<drivers::UsbDaq>(usb);  // throws naming VID:PID
    parts_->analog = parts_->usb_daq.get();
    parts_->digital = parts_->usb_daq.get();
    parts_->drive = parts_->usb_daq.get();
    spdlog::info("DAQ: USB {:04x}:{:04x}", usb.vendor_id, usb.product_id);
  } else if (config_.daq.kind == "modbus") {
    parts_->daq = std::make_unique<drivers::ModbusDaq>(config_.daq.modbus);
    parts_->analog = parts_->daq.get();
    parts_->digital = parts_->daq.get();
    parts_->drive = parts_->daq.get();
    spdlog::info("DAQ: Modbus {} {}", config_.daq.modbus.transport,
                 config_.daq.modbus.transport == "tcp"
                     ? config_.daq.modbus.host + ":" + std::to_string(config_.daq.modbus.port)
                     : config_.daq.modbus.serial_device);
  } else {
    throw std::runtime_error("daq.kind = \"" + config_.daq.kind +
                             "\" is not available in this build");
  }
  if (config_.gpio.enabled) start_gpio();
}

void RigdApp::start_gpio() {
  drivers::GpioSettings g;
  g.chip = config_.gpio.chip;
  g.home_line = static_cast<unsigned>(config_.gpio.home_line);
  g.end_line = static_cast<unsigned>(config_.gpio.end_line);
  g.estop_line = static_cast<unsigned>(config_.gpio.estop_line);
  g.motor_enable_line = static_cast<unsigned>(config_.gpio.motor_enable_line);
  g.camera_trigger_line = static_cast<unsigned>(config_.gpio.camera_trigger_line);
  g.estop_active_low = config_.gpio.estop_active_low;
  g.debounce_ns = static_cast<std::int64_t>(config_.gpio.debounce_us) * 1000;
  parts_->gpio =
      std::make_unique<drivers::GpioDigitalIo>(g, parts_->clock);  // throws naming chip and line
  parts_->digital =
      parts_->gpio.get();  // switches, e-stop, enable and trigger on GPIO; analog stays on the DAQ
  spdlog::info("GPIO: chip {} (home {}, end {}, e-stop {}, enable {}, trigger {})", g.chip,
               g.home_line, g.end_line, g.estop_line, g.motor_enable_line, g.camera_trigger_line);
}

void RigdApp::start_loop() {
  parts_->channels = std::make_unique<rt::LoopChannels>();
  rt::LoopHardware hw{parts_->analog, parts_->digital, parts_->drive, &parts_->clock};
  rt::LoopSettings loop_settings = config_.loop;
  loop_settings.daq_watchdog_ms = config_.daq.modbus.watchdog_ms;  // the USB DAQ is given the same
  parts_->loop = std::make_unique<rt::ControlLoop>(loop_settings, hw, *parts_->channels);
  RtThreadReport memory = lock_process_memory(config_.thread.lock_memory);
  parts_->rt_report = memory;
  parts_->wake_latency =
      std::make_unique<drivers::CpuWakeLatencyRequest>(config_.thread.cpu_wake_latency_us);
  if (config_.thread.cpu_wake_latency_us >= 0 && !parts_->wake_latency->held()) {
    parts_->rt_report.warnings.push_back(parts_->wake_latency->why_not() +
                                         ": idle CPUs may wake late for the loop and the DAQ");
  }
  RtThreadOptions options{config_.thread.priority, config_.thread.cpu, config_.thread.lock_memory};
  rt_thread_ = start_rt_thread(
      options, [this] { parts_->loop->run(stop_loop_); }, parts_->rt_report);
  for (const auto& warning : parts_->rt_report.warnings) spdlog::warn("RT: {}", warning);
  spdlog::info(
      "RT loop at {} Hz ({}{}{}{})", config_.loop.rate_hz,
      parts_->rt_report.realtime ? "SCHED_FIFO" : "normal scheduling",
      !parts_->rt_report.memory_locked           ? ""
      : parts_->rt_report.memory_locked_on_fault ? ", memory locked as touched (sanitizer build)"
                                                 : ", memory locked",
      parts_->rt_report.pinned ? ", on CPU " + std::to_string(config_.thread.cpu) : "",
      parts_->wake_latency->held()
          ? ", CPU wake-up <= " + std::to_string(config_.thread.cpu_wake_latency_us) + " us"
          : "");
}

void RigdApp::start_services() {
  std::filesystem::create_directories(
      std::filesystem::absolute(config_.archive.path).parent_path());
  parts_->recorder = std::make_unique<Recorder>(*parts_->channels, config_.archive.path,
                                                config_.archive.flush_interval_ms);
  const std::string refused =
      parts_->recorder->start(parts_->rt_report.realtime ? config_.archive.recorder_priority : 0);
  if (!refused.empty()) spdlog::warn("archive: {}", refused);
  parts_->hub = std::make_unique<StreamHub>(*parts_->channels, config_.loop.motion.surface_mm,
                                            config_.stream.batch_ms);
  try {
    auto overlay =
        std::make_shared<const model::ForceModel>(model::ForceModel::load(config_.model.file));
    if (overlay->form == model::ModelForm::kPrinted)
      spdlog::warn("model: {}", model::printed_form_warning(*overlay));
    parts_->hub->set_model(std::move(overlay));
  } catch (const std::exception& e) {
    spdlog::warn("model: {} (the live overlay shows no model curve)", e.what());
  }
  api::ApiContext& c = parts_->api_context;
  c.channels = parts_->channels.get();
  c.recorder_stats = &parts_->recorder->stats();
  c.hub = parts_->hub.get();
  c.config = &config_;
  c.realtime = parts_->rt_report.realtime;
  c.version = software_version();
  c.guard = api::RequestGuard(config_.api.allowed_origins, machine_host_name());
  if (!config_.api.token_file.empty())
    c.auth = api::ApiAuth(api::load_token(config_.api.token_file));
  drivers::ModbusDaq* daq = parts_->daq.get();
  if (daq != nullptr)
    c.extra_metrics = [daq] {
      const auto n = daq->counters();
      return "# TYPE rigd_modbus_timeouts_total counter\nrigd_modbus_timeouts_total " +
             std::to_string(n.timeouts) +
             "\n# TYPE rigd_modbus_link_errors_total counter\nrigd_modbus_link_errors_total " +
             std::to_string(n.link_errors) +
             "\n# TYPE rigd_modbus_bad_data_total counter\nrigd_modbus_bad_data_total " +
             std::to_string(n.bad_data) + "\n";
    };
  parts_->lab = std::make_unique<LabWorker>(config_.archive.path, *parts_->hub);
  c.lab = parts_->lab.get();
  parts_->api = std::make_unique<api::ApiServer>(c, config_.api.bind, config_.api.port);
  parts_->hub->add_sink(parts_->api.get());
  parts_->haptic = std::make_unique<HapticService>(config_, *parts_->channels, *parts_->api);
  c.haptic = parts_->haptic.get();
  if (config_.stream.udp_enabled) {
    parts_->udp = std::make_unique<UdpPublisher>(config_.stream.udp_host, config_.stream.udp_port);
    parts_->hub->add_sink(parts_->udp.get());
  }
  start_camera();
  start_lab_archive();
  parts_->hub->start();
  parts_->api->start();
}

void RigdApp::start_camera() {
  if (config_.camera.kind == "none") return;
  drivers::CameraSettings settings;
  settings.width = config_.camera.width;
  settings.height = config_.camera.height;
  settings.frame_rate_hz = config_.camera.frame_rate_hz;
  settings.exposure_us = config_.camera.exposure_us;
  settings.hardware_trigger = config_.camera.hardware_trigger;
  settings.packet_size = config_.camera.packet_size;
  std::unique_ptr<drivers::Camera> camera;
  if (config_.camera.kind == "sim") {
    rt::LoopChannels* channels = parts_->channels.get();
    const double surface = config_.loop.motion.surface_mm;
    camera = std::make_unique<drivers::SimCamera>(settings, [channels, surface] {
      const rt::StatusSnapshot st = channels->status.read();
      return drivers::CameraScene{st.position_mm, surface, st.force_N};
    });
  } else if (config_.camera.kind == "v4l2") {
    camera = std::make_unique<drivers::V4l2Camera>(
        config_.camera.id.empty() ? "/dev/video0" : config_.camera.id, settings);
  } else if (config_.camera.kind == "aravis") {
    camera = std::make_unique<drivers::AravisCamera>(config_.camera.id,
                                                     settings);  // throws naming the camera
  } else {
    throw std::runtime_error("camera.kind = \"" + config_.camera.kind +
                             "\" is not available in this build");
  }
  std::unique_ptr<FrameRecorder> recorder;
  if (config_.camera.record_frames) {
    const std::string dir =
        config_.camera.frames_dir.empty()
            ? (std::filesystem::absolute(config_.archive.path).parent_path() / "frames").string()
            : config_.camera.frames_dir;
    Recorder* archive_writer = parts_->recorder.get();
    recorder = std::make_unique<FrameRecorder>(
        [archive_writer](std::vector<archive::FrameRow> rows) {
          archive_writer->add_frames(std::move(rows));
        },
        dir, config_.loop.rate_hz);
    spdlog::info("camera: {}; frames of each run go to {}", camera->describe(), dir);
  }
  parts_->camera = std::make_unique<CameraService>(
      std::move(camera), *parts_->channels, config_.stream.camera_max_hz, std::move(recorder),
      config_.camera.lost_after_ms);
  parts_->camera->add_sink(parts_->api.get());
  parts_->camera->start();
}

void RigdApp::start() {
  start_drivers();
  start_loop();
  start_services();
}

void RigdApp::start_lab_archive() {
  if (!config_.lab_archive.enabled) return;
  parts_->lab_replicator = std::make_unique<lab_archive::LabReplicator>(
      config_.lab_archive, config_.archive.path, software_version());
  parts_->lab_replicator->start();  // throws naming the password file if it is unsafe
  lab_archive::LabReplicator* replicator = parts_->lab_replicator.get();
  parts_->api_context.lab_archive_status = [replicator] {
    return lab_archive::status_json(replicator->status());
  };
  parts_->api_context.lab_archive_connection = lab_archive::connection_params(config_.lab_archive);
  spdlog::info("lab archive: replicating as rig {}", replicator->status().rig_id);
}

bool RigdApp::loop_alive() {
  if (!parts_->channels) return false;
  const std::uint64_t cycles = parts_->channels->counters.cycles.load();
  const bool alive = cycles != last_cycles_seen_;
  last_cycles_seen_ = cycles;
  return alive;
}

void RigdApp::shutdown() {
  if (rt_thread_.joinable()) {
    stop_loop_.store(true);
    rt_thread_.join();  // the loop writes motor off on its way out
    parts_->wake_latency.reset();
    spdlog::info("RT loop stopped, motor off");
  }
  if (parts_->haptic) parts_->haptic->stop();
  if (parts_->lab_replicator) parts_->lab_replicator->stop();
  if (parts_->camera) parts_->camera->stop();
  if (parts_->hub) parts_->hub->stop();
  if (parts_->api) parts_->api->stop();
  if (parts_->recorder) parts_->recorder->stop();
}

}  // namespace rig::service
