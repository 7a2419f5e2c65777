#include "haptic_command.hpp"

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>

#include "playback.hpp"
#include "run_loader.hpp"

namespace rig::cli {
namespace {

struct HapticOptions {
  std::string device = "sim";
  std::string source = "model";
  std::string model_file;   // reference model (and the model source's default)
  std::string compare_run;  // a run to compare the felt force with
  double velocity_mm_s = 2.0;
  double iop_mmHg = 15.0;
  double depth_mm = 0.0;  // 0: automatic
  int mesh_n = 13;
  bool virtual_time = false;
  std::string library = "libHD.so";
  double max_s = 120.0;
};

std::atomic<bool> g_interrupted{false};
extern "C" void on_interrupt(int /*signal*/) {
  g_interrupted.store(true);
}

nlohmann::json optional_number(const std::optional<haptic::ErrorFigures>& figures,
                               double haptic::ErrorFigures::*field) {
  return figures ? nlohmann::json((*figures).*field) : nlohmann::json(nullptr);
}

nlohmann::json result_json(const HapticOptions& o, const haptic::PlaybackResult& result,
                           const std::string& device) {
  const haptic::SessionReport& r = result.report;
  return {{"device", device},
          {"source", o.source},
          {"velocity_mm_s", o.velocity_mm_s},
          {"iop_mmHg", o.iop_mmHg},
          {"rate_hz", r.rate_hz},
          {"ticks", r.ticks},
          {"overruns", r.overruns},
          {"late_ticks", r.late_ticks},
          {"tick_p50_us", r.tick_p50_us},
          {"tick_p99_us", r.tick_p99_us},
          {"tick_max_us", r.tick_max_us},
          {"rmse_vs_model_N", optional_number(result.vs_model, &haptic::ErrorFigures::rmse_N)},
          {"max_vs_model_N", optional_number(result.vs_model, &haptic::ErrorFigures::max_N)},
          {"max_vs_model_at_mm",
           optional_number(result.vs_model, &haptic::ErrorFigures::max_at_depth_mm)},
          {"rmse_vs_run_N", optional_number(result.vs_run, &haptic::ErrorFigures::rmse_N)},
          {"max_vs_run_N", optional_number(result.vs_run, &haptic::ErrorFigures::max_N)},
          {"samples_in_contact",
           result.vs_model ? nlohmann::json(result.vs_model->samples) : nlohmann::json(nullptr)},
          {"nonfinite_forces", r.nonfinite_forces},
          {"clamped_ticks", r.clamped_ticks},
          {"slew_limited_ticks", r.slew_limited_ticks},
          {"watchdog_tripped", r.watchdog_tripped},
          {"longest_stall_ms", r.longest_stall_ms},
          {"longest_tick_gap_ms", r.longest_tick_gap_ms},
          {"fault", r.fault.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.fault)},
          {"force_limit_N", r.force_limit_N},
          {"mesh_vertices", r.mesh_vertices},
          {"mesh_springs", r.mesh_springs}};
}

void print_result(const CliContext& c, const nlohmann::json& j) {
  if (c.json()) {
    std::cout << j.dump() << "\n";
    return;
  }
  std::vector<std::pair<std::string, std::string>> pairs;
  for (const auto& [key, value] : j.items()) {
    pairs.emplace_back(key, value.is_string()         ? value.get<std::string>()
                            : value.is_number_float() ? fixed(value.get<double>(), 6)
                                                      : value.dump());
  }
  print_pairs(pairs);
}

// The live rig's force is in rigd: the session runs there, this follows it.
int haptic_via_rigd(const CliContext& c, const HapticOptions& o) {
  const ApiClient client = c.client();
  const nlohmann::json request = {
      {"device", o.device},     {"source", o.source}, {"velocity_mm_s", o.velocity_mm_s},
      {"iop_mmHg", o.iop_mmHg}, {"mesh_n", o.mesh_n}, {"max_s", o.max_s}};
  const HttpReply started = client.post("/api/haptic", request.dump());
  if (started.status != 202)
    throw std::runtime_error("rigd refused the haptic session: " +
                             parse_reply(started, "/api/haptic").value("error", started.body));
  nlohmann::json status;
  bool stop_sent = false;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
    if (g_interrupted.load() && !stop_sent)
      stop_sent = client.post("/api/haptic/stop").status == 200;
    status = parse_reply(client.get("/api/haptic"), "/api/haptic");
  } while (status.value("state", "") == "running");
  print_result(c, status);
  return status.value("state", "") == "done" ? 0 : 3;
}

int haptic(const CliContext& c, const HapticOptions& o) {
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);
  haptic::PlaybackOptions p;
  p.device = o.device;
  p.source = haptic::SourceSpec::parse(o.source);
  if (p.source.kind == haptic::SourceSpec::Kind::kLive) return haptic_via_rigd(c, o);
  p.velocity_mm_s = o.velocity_mm_s;
  p.iop_mmHg = o.iop_mmHg;
  if (o.depth_mm > 0.0) p.depth_mm = o.depth_mm;
  p.mesh_n = o.mesh_n;
  p.real_time = !o.virtual_time;
  p.library = o.library;
  p.max_s = o.max_s;
  const bool model_source = p.source.kind == haptic::SourceSpec::Kind::kModel;
  const std::string model_file = default_model_file(
      model_source && !p.source.argument.empty() ? p.source.argument : o.model_file);
  const model::ForceModel reference = model::ForceModel::load(model_file);
  std::optional<model::RunData> run;
  const std::string run_name =
      p.source.kind == haptic::SourceSpec::Kind::kRun ? p.source.argument : o.compare_run;
  if (!run_name.empty()) run = load_runs({run_name}, c.archive_path).front();
  haptic::Playback playback(p, reference, std::move(run));
  const haptic::PlaybackResult result = playback.run(nullptr, &g_interrupted);
  print_result(c, result_json(o, result, playback.device_name()));
  if (!result.report.fault.empty()) {
    std::cerr << "rig haptic: " << result.report.fault << "\n";
    return 3;
  }
  return 0;
}

}  // namespace

void add_haptic_command(CLI::App& app, CliContext& c, int& exit_code) {
  auto o = std::make_shared<HapticOptions>();
  CLI::App* cmd = app.add_subcommand(
      "haptic",
      "feel the model, a recorded run or the live rig on a Phantom (or the simulated one)");
  cmd->add_option("--device", o->device,
                  "sim (simulated Phantom, virtual hand) or phantom (OpenHaptics)")
      ->check(CLI::IsMember({"sim", "phantom"}));
  cmd->add_option("--source", o->source, "model, model:FILE, run:ID|CSV or live (through rigd)");
  cmd->add_option("--model", o->model_file, "reference model file (default: paper-interpreted)");
  cmd->add_option("--compare-run", o->compare_run,
                  "a run (archive id or CSV) to compare the felt force with");
  cmd->add_option("--velocity", o->velocity_mm_s, "virtual hand's velocity [mm/s]")
      ->check(CLI::Range(0.1, 10.0));
  cmd->add_option("--iop", o->iop_mmHg, "IOP the model is evaluated at [mmHg]")
      ->check(CLI::Range(5.0, 40.0));
  cmd->add_option("--depth", o->depth_mm,
                  "virtual hand's deepest point [mm] (default: past the model's final depth)");
  cmd->add_option("--mesh-n", o->mesh_n,
                  "mass-spring vertices per side (13: 169 vertices, 886 springs)")
      ->check(CLI::Range(3, 256));
  cmd->add_flag("--virtual-time", o->virtual_time,
                "sim: run the servo as fast as possible on a virtual clock");
  cmd->add_option("--library", o->library, "OpenHaptics HD library to dlopen");
  cmd->add_option("--max-seconds", o->max_s, "stop the session after this long [s]")
      ->check(CLI::PositiveNumber);
  cmd->callback([&c, &exit_code, o] { exit_code = haptic(c, *o); });
}

}  // namespace rig::cli
