#include "demo_command.hpp"

#include <nlohmann/json.hpp>

#include <boost/asio/ip/tcp.hpp>

#include <csignal>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <regex>
#include <thread>

#include "archive.hpp"
#include "child_process.hpp"
#include "cut_summary.hpp"
#include "shared_cpu.hpp"
#include "timing_fault.hpp"

namespace rig::cli {
namespace {

struct DemoOptions {
  std::string sim = "rig-sim";
  std::string rigd = "rigd";
  std::string config = "config/rigd.sim.toml";
  std::string web_root;
  std::string state_dir = "demo-state";
  int port = 8080;
  int cpu = -1;  // rig-sim's and rigd's loop's CPU, -1 = chosen (pick_shared_cpu)
  bool once = false;
  double iop_mmHg = 15.0;
  double velocity_mm_s = 2.0;
  double depth_mm = 14.0;
};

bool port_free(int port) {
  try {
    boost::asio::io_context io;
    boost::asio::ip::tcp::acceptor acceptor(
        io, {boost::asio::ip::make_address("127.0.0.1"), static_cast<unsigned short>(port)});
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

// A fault of the loop's timing (the DAQ link, the DAQ's watchdog, loop overruns): on a real
// rig a fault of the machine; here rigd's 1 kHz loop and the simulated DAQ share the CPUs
// with whatever else runs, so the demo says so and cuts again (docs/faults.md).
struct TimingFault : std::runtime_error {
  using std::runtime_error::runtime_error;
};

nlohmann::json wait_state(const ApiClient& api,
                          const std::function<bool(const nlohmann::json&)>& done, int timeout_s,
                          const std::string& what) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(timeout_s);
  while (std::chrono::steady_clock::now() < end) {
    nlohmann::json s = nlohmann::json::parse(api.get("/api/status").body);
    if (done(s)) return s;
    if (s["state"] == "Fault" || s["state"] == "EStop") {
      const std::string why = what + ": rig went to " + s["state"].get<std::string>() + ": " +
                              s["fault"].get<std::string>();
      if (s["state"] == "Fault" && is_timing_fault(s["fault"])) throw TimingFault(why);
      throw std::runtime_error(why);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  throw std::runtime_error(what + ": no result within " + std::to_string(timeout_s) + " s");
}

// A moving command is refused while the loop's last 3 DAQ requests in a row went unanswered
// ("DAQ link is down"); on a busy machine that lasts a few ms. The demo asks again for up to
// 3 s before it gives the refusal as its answer (a link that stays down faults the rig).
HttpReply post_when_linked(const ApiClient& api, const std::string& path, const std::string& body) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(3);
  HttpReply reply = api.post(path, body);
  while (reply.status != 200 && reply.body.find("DAQ link is down") != std::string::npos &&
         std::chrono::steady_clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    reply = api.post(path, body);
  }
  return reply;
}

void command(const ApiClient& api, const std::string& name, const std::string& body = "") {
  const HttpReply reply = post_when_linked(api, "/api/" + name, body);
  if (reply.status != 200) throw std::runtime_error(name + " refused: " + reply.body);
}

std::int64_t run_the_cut(const ApiClient& api, const DemoOptions& o, bool quiet) {
  auto say = [quiet](const std::string& text) {
    if (!quiet) std::cerr << "[demo] " << text << std::endl;
  };
  say("homing");
  command(api, "home");
  wait_state(
      api, [](const nlohmann::json& s) { return s["state"] == "Ready"; }, 60, "homing");
  say("taring the load cell");
  command(api, "tare");
  wait_state(
      api, [](const nlohmann::json& s) { return s["tared"] == true; }, 10, "tare");
  say("cutting: IOP " + fixed(o.iop_mmHg, 0) + " mmHg, " + fixed(o.velocity_mm_s, 1) + " mm/s, " +
      fixed(o.depth_mm, 0) + " mm");
  const nlohmann::json body = {{"eye_id", "DEMO-" + std::to_string(std::time(nullptr))},
                               {"iop_mmHg", o.iop_mmHg},
                               {"velocity_mm_s", o.velocity_mm_s},
                               {"depth_mm", o.depth_mm},
                               {"post_mortem_h", 2.0},
                               {"operator", "rig demo"},
                               {"meta", {{"specimen", "simulated ovine eye"}}}};
  const HttpReply reply = post_when_linked(api, "/api/run", body.dump());
  if (reply.status != 200) throw std::runtime_error("run refused: " + reply.body);
  const std::int64_t run_id = nlohmann::json::parse(reply.body)["run_id"];
  wait_state(
      api, [](const nlohmann::json& s) { return s["state"] == "Done"; }, 120, "cut");
  say("run " + std::to_string(run_id) + " done");
  return run_id;
}

nlohmann::json summarize(const CliContext& c, const ApiClient& api, std::int64_t run_id,
                         const std::string& archive_path) {
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the recorder commits every 50 ms
  archive::Archive archive(archive_path, true);
  const model::RunData run = archive.load_run(run_id);
  const nlohmann::json status = nlohmann::json::parse(api.get("/api/status").body);
  std::unique_ptr<model::ForceModel> force_model;
  try {
    force_model =
        std::make_unique<model::ForceModel>(model::ForceModel::load(status["model_file"]));
  } catch (const std::exception& e) {
    std::cerr << "[demo] warning: " << e.what() << "\n";
  }
  const model::CutSummary s = model::summarize_cut(run, force_model.get());
  nlohmann::json j = {{"run_id", run_id},
                      {"outcome", archive.find_run(run_id)->outcome},
                      {"samples", s.samples},
                      {"commanded_velocity_mm_s", s.commanded_velocity_mm_s},
                      {"velocity_mm_s", s.velocity_mm_s},
                      {"longest_gap_ms", s.longest_gap_ms},
                      {"velocity_error_pct", s.velocity_error_pct},
                      {"peak_force_N", s.peak_force_N},
                      {"x_at_peak_mm", s.x_at_peak_mm},
                      {"max_depth_mm", s.max_depth_mm},
                      {"loop_jitter_p99_us", status["loop"]["jitter_p99_us"]},
                      {"loop_overruns", status["loop"]["overruns"]},
                      {"daq_misses", status["loop"]["io_misses"]},
                      {"realtime", status["loop"]["realtime"]},
                      {"overlay_url", api.url() + "/"}};
  if (s.model_rmse_N) {
    j["model_rmse_N"] = *s.model_rmse_N;
    j["model_file"] = status["model_file"];
  }
  (void)c;
  return j;
}

void print_summary(const nlohmann::json& j) {
  print_pairs(
      {{"run", std::to_string(j["run_id"].get<std::int64_t>()) + " (" +
                   j["outcome"].get<std::string>() + ")"},
       {"samples", std::to_string(j["samples"].get<std::size_t>())},
       {"velocity", fixed(j["velocity_mm_s"], 4) + " mm/s (commanded " +
                        fixed(j["commanded_velocity_mm_s"], 2) + ", error " +
                        fixed(j["velocity_error_pct"], 3) + " %; longest gap between samples " +
                        fixed(j["longest_gap_ms"], 0) + " ms)"},
       {"puncture peak",
        fixed(j["peak_force_N"], 4) + " N at x = " + fixed(j["x_at_peak_mm"], 3) + " mm"},
       {"model RMSE", j.contains("model_rmse_N") ? fixed(j["model_rmse_N"], 4) + " N vs " +
                                                       j["model_file"].get<std::string>()
                                                 : "-"},
       {"loop", "jitter p99 " + fixed(j["loop_jitter_p99_us"], 0) + " us, overruns " +
                    std::to_string(j["loop_overruns"].get<std::int64_t>()) +
                    (j["realtime"] ? ", SCHED_FIFO" : ", not real-time")},
       {"accidental faults", std::to_string(j["accidental_faults"].get<int>()) +
                                 " (timing faults of the simulated rig, cut again)"},
       {"live overlay", j["overlay_url"]}});
}

// rigd against the demo's rig-sim: its port, the demo's archive, the API port asked for (when
// free), the shared CPU (-1 = none) and the page's assets.
std::vector<std::string> rigd_arguments(const DemoOptions& o, const std::string& sim_port,
                                        const std::string& archive_path, int cpu) {
  const int api_port = port_free(o.port) ? o.port : 0;
  std::vector<std::string> args = {o.rigd,
                                   "--config",
                                   o.config,
                                   "--set",
                                   "daq.port=" + sim_port,
                                   "--set",
                                   "api.port=" + std::to_string(api_port),
                                   "--set",
                                   "archive.path=\"" + archive_path + "\""};
  if (cpu >= 0) args.insert(args.end(), {"--set", "loop.cpu=" + std::to_string(cpu)});
  if (!o.web_root.empty())
    args.insert(args.end(), {"--set", "api.web_root=\"" + o.web_root + "\""});
  return args;
}

// Keeps the rig serving the overlay until Ctrl-C (or SIGTERM).
void serve_until_interrupted(const ApiClient& api, const std::string& archive_path) {
  // Block Ctrl-C before saying it stops the demo: one pressed right after the line must
  // end the demo the orderly way, not kill it.
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  std::cerr << "[demo] live overlay at " << api.url() << "/  (runs stay in " << archive_path
            << "); Ctrl-C to stop" << std::endl;
  int signal = 0;
  sigwait(&signals, &signal);
}

int run_demo(const CliContext& c, const DemoOptions& o) {
  std::filesystem::create_directories(o.state_dir);
  const std::string state = std::filesystem::absolute(o.state_dir).string();
  const std::string archive_path = state + "/archive.sqlite";
  const int cpu =
      o.cpu >= 0 ? o.cpu
                 : pick_shared_cpu();  // rig-sim and rigd's loop stop together (shared_cpu.hpp)
  std::vector<std::string> sim_args = {o.sim, "--port", "0"};
  if (cpu >= 0) sim_args.insert(sim_args.end(), {"--cpu", std::to_string(cpu)});
  ChildProcess sim(sim_args, state + "/rig-sim.log");
  const std::string listening = sim.wait_for_line("listening on", 10000);
  const std::vector<std::string> rigd_args =
      rigd_arguments(o, listening.substr(listening.rfind(':') + 1), archive_path, cpu);
  ChildProcess rigd(rigd_args, state + "/rigd.log");
  const std::string ready = rigd.wait_for_line("ready, API on", 15000);
  const ApiClient api(ready.substr(ready.find("http://")), "");
  nlohmann::json summary;
  constexpr int kCuts = 3;  // a timing fault is reported and the cut tried again, twice at most
  for (int attempt = 1; summary.is_null(); ++attempt) {
    try {
      summary = summarize(c, api, run_the_cut(api, o, c.json()), archive_path);
      summary["accidental_faults"] = attempt - 1;
    } catch (const TimingFault& e) {
      std::cerr << "[demo] " << e.what()
                << "\n[demo] a timing fault of the simulated rig: its 1 kHz loop and simulated DAQ "
                   "share this"
                << " machine's CPUs with everything else (logs: " << state << "/rigd.log)\n";
      if (attempt == kCuts) return 1;
      std::cerr << "[demo] reset, cutting again (" << attempt + 1 << " of " << kCuts << ")\n";
      api.post("/api/reset");
      try {  // rigd reconnects to the DAQ on its own; homing is refused until it has
        wait_state(
            api, [](const nlohmann::json& s) { return s["interlocks"]["link_ok"] == true; }, 10,
            "reconnecting to the DAQ");
      } catch (const std::exception& reconnect) {
        std::cerr << "[demo] failed: " << reconnect.what() << "\n";
        return 1;
      }
    } catch (const std::exception& e) {
      std::cerr << "[demo] failed: " << e.what() << "\n[demo] logs: " << state << "/rigd.log, "
                << state << "/rig-sim.log\n";
      return 1;
    }
  }
  if (c.json())
    std::cout << summary.dump() << std::endl;
  else
    print_summary(summary);
  std::cout.flush();
  if (!o.once) serve_until_interrupted(api, archive_path);
  rigd.stop();
  sim.stop();
  return summary["outcome"] == "completed" ? 0 : 1;
}

}  // namespace

void add_demo_command(CLI::App& app, CliContext& c, int& exit_code) {
  auto o = std::make_shared<DemoOptions>();
  CLI::App* demo =
      app.add_subcommand("demo", "simulated cut with the live overlay and the model comparison");
  demo->add_option("--sim", o->sim, "rig-sim executable");
  demo->add_option("--rigd", o->rigd, "rigd executable");
  demo->add_option("--config", o->config, "rigd config for the simulated rig");
  demo->add_option("--web-root", o->web_root, "overlay page directory");
  demo->add_option("--state-dir", o->state_dir, "where the demo's archive and logs go");
  demo->add_option("--port", o->port, "API port (a free one if taken)");
  demo->add_option("--cpu", o->cpu,
                   "CPU for rig-sim and rigd's loop together, -1 = chosen among the allowed ones")
      ->check(CLI::Range(-1, 1023));
  demo->add_option("--iop", o->iop_mmHg, "IOP [mmHg]");
  demo->add_option("--velocity", o->velocity_mm_s, "cutting velocity [mm/s]");
  demo->add_option("--depth", o->depth_mm, "insertion depth [mm]");
  demo->add_flag("--once", o->once, "print the summary and exit (no overlay)");
  demo->callback([&c, &exit_code, o] { exit_code = run_demo(c, *o); });
}

}  // namespace rig::cli
