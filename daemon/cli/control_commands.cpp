#include "control_commands.hpp"

#include <nlohmann/json.hpp>

#include <atomic>
#include <chrono>
#include <csignal>
#include <iostream>
#include <thread>

#include "lab_commands.hpp"
#include "rig/proto/messages.hpp"

namespace rig::cli {
namespace {

std::atomic<bool> g_interrupted{false};

int show_status(const CliContext& c) {
  const HttpReply reply = c.client().get("/api/status");
  const nlohmann::json s = parse_reply(reply, "status");
  if (c.json()) {
    std::cout << s.dump() << "\n";
    return reply.status == 200 ? 0 : 1;
  }
  const auto& l = s["loop"];
  const auto& i = s["interlocks"];
  print_pairs(
      {{"state", s["state"].get<std::string>() +
                     (s["phase"] != "none" ? " (" + s["phase"].get<std::string>() + ")" : "")},
       {"fault", s["fault"]},
       {"homed / tared",
        std::string(s["homed"] ? "yes" : "no") + " / " + (s["tared"] ? "yes" : "no")},
       {"position", fixed(s["position_mm"], 3) + " mm"},
       {"force", fixed(s["force_N"], 4) + " N"},
       {"IOP", fixed(s["iop_mmHg"], 2) + " mmHg (target " + fixed(s["iop_target_mmHg"], 1) +
                   (s["iop_settled"] ? ", settled)" : ")")},
       {"velocity", fixed(s["velocity_mm_s"], 3) + " mm/s"},
       {"motor", std::string(s["motor_enabled"] ? "enabled, " : "off, ") +
                     fixed(s["motor_volts"], 2) + " V"},
       {"interlocks", std::string("home ") + (i["home_limit"] ? "ON" : "off") + ", end " +
                          (i["end_limit"] ? "ON" : "off") + ", e-stop " +
                          (i["estop_input"] ? "PRESSED" : "off") + ", DAQ link " +
                          (i["link_ok"] ? "ok" : "DOWN")},
       {"run", s["run_id"].get<std::int64_t>() != 0
                   ? std::to_string(s["run_id"].get<std::int64_t>())
                   : "-"},
       {"loop", fixed(l["rate_hz"], 0) + " Hz" +
                    (l["realtime"] ? " SCHED_FIFO" : " (not real-time)") + ", jitter p50/p99/max " +
                    fixed(l["jitter_p50_us"], 0) + "/" + fixed(l["jitter_p99_us"], 0) + "/" +
                    fixed(l["jitter_max_us"], 0) + " us, overruns " +
                    std::to_string(l["overruns"].get<std::int64_t>())},
       {"model", s["model_file"]}});
  if (s.contains("lab_archive"))
    print_pairs({{"lab archive", describe_lab_archive_status(s["lab_archive"])}});
  return 0;
}

int send_command(const CliContext& c, const std::string& name) {
  const HttpReply reply = c.client().post("/api/" + name);
  const nlohmann::json j = parse_reply(reply, name);
  if (c.json()) {
    std::cout << j.dump() << "\n";
  } else if (j.contains("error")) {
    std::cerr << name << ": " << j["error"].get<std::string>() << "\n";
  } else {
    std::cout << name << ": " << j["result"].get<std::string>() << " (state "
              << j["state"].get<std::string>() << ")\n";
  }
  return reply.status == 200 ? 0 : 1;
}

// Polls the status until the rig leaves Homing; false (with the status in `last`) on time-out.
bool wait_while_homing(const CliContext& c, double timeout_s, nlohmann::json& last) {
  const ApiClient client = c.client();
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (true) {
    last = parse_reply(client.get("/api/status"), "status");
    if (last["state"] != "Homing") return true;
    if (std::chrono::steady_clock::now() >= end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

constexpr double kHomingTimeout_s = 120.0;  // 60 mm of travel at the slowest homing speed, and back

// Taring averages safety.tare_cycles readings (0.5 s): a `rig run` right after must find it done.
bool wait_until_tared(const CliContext& c) {
  const ApiClient client = c.client();
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (std::chrono::steady_clock::now() < end) {
    const nlohmann::json s = parse_reply(client.get("/api/status"), "status");
    if (s["tared"] == true && s["taring"] != true) return true;
    if (s["state"] == "Fault" || s["state"] == "EStop") break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  std::cerr << "tare: the load cell was not tared within 10 s\n";
  return false;
}

int home_rig(const CliContext& c, bool wait) {
  if (!wait) return send_command(c, "home");
  const HttpReply reply = c.client().post("/api/home");
  const nlohmann::json j = parse_reply(reply, "home");
  if (reply.status != 200) {
    std::cerr << "home: "
              << (j.contains("error") ? j["error"].get<std::string>()
                                      : j.value("result", "refused"))
              << "\n";
    return 1;
  }
  if (!c.json()) std::cerr << "home: homing (waits until parked; --no-wait returns at once)\n";
  nlohmann::json s;
  if (!wait_while_homing(c, kHomingTimeout_s, s)) {
    std::cerr << "home: still homing after " << kHomingTimeout_s << " s (position "
              << fixed(s["position_mm"], 2) << " mm)\n";
    return 1;
  }
  const bool parked = s["state"] == "Ready" && s["homed"] == true;
  if (c.json()) {
    std::cout << s.dump() << "\n";
  } else if (parked) {
    std::cout << "home: parked at " << fixed(s["position_mm"], 2) << " mm (state Ready)\n";
  } else {
    std::cerr << "home: ended in " << s["state"].get<std::string>()
              << (s["fault"] != "none" ? ": " + s["fault"].get<std::string>() : "") << "\n";
  }
  return parked ? 0 : 1;
}

int list_runs(const CliContext& c) {
  const HttpReply reply = c.client().get("/api/runs");
  const nlohmann::json j = parse_reply(reply, "runs");
  if (c.json()) {
    std::cout << j.dump() << "\n";
    return 0;
  }
  Rows rows;
  for (const auto& r : j["runs"]) {
    rows.push_back(
        {std::to_string(r["run_id"].get<std::int64_t>()), r["eye_id"], r.value("started_at", ""),
         r.contains("iop_mmHg") ? fixed(r["iop_mmHg"], 1) : "-",
         r.contains("velocity_mm_s") ? fixed(r["velocity_mm_s"], 2) : "-",
         std::to_string(r["samples"].get<std::int64_t>()), r["outcome"], r.value("reason", "")});
  }
  print_table({"run", "eye", "started (UTC)", "IOP mmHg", "v mm/s", "samples", "outcome", "reason"},
              rows);
  return 0;
}

}  // namespace

namespace {

struct RunOptions {
  proto::RunRequest request;
  double hold_s = 0.0;
  double post_mortem_h = -1.0;
  std::string operator_name;
  std::string notes;
  std::vector<std::string> meta;
  bool no_wait = false;
};

void on_interrupt(int /*signal*/) {
  g_interrupted.store(true);
}

// The run's archive entry once the recorder has closed it: the loop's state says the run
// ended a moment before the recorder's last commit writes its outcome (longer on a busy
// machine), so an outcome still "recording" is asked again, for up to 10 s.
nlohmann::json archived_run_once_closed(const CliContext& c, std::int64_t run_id) {
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (true) {
    nlohmann::json detail =
        parse_reply(c.client().get("/api/runs/" + std::to_string(run_id)), "run detail");
    const std::string outcome = detail["run"].value("outcome", "");
    if ((outcome != "recording" && outcome != "armed") ||
        std::chrono::steady_clock::now() > give_up)
      return detail;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

nlohmann::json wait_for_run_end(const CliContext& c, bool print_progress) {
  std::signal(SIGINT, on_interrupt);
  const ApiClient client = c.client();
  std::string last_line;
  while (true) {
    if (g_interrupted.exchange(false)) {
      std::cerr << "\ninterrupted: stopping the rig\n";
      client.post("/api/stop");
    }
    nlohmann::json s = parse_reply(client.get("/api/status"), "status");
    const std::string state = s["state"];
    if (print_progress && !c.json()) {
      const std::string line = state + " " + s["phase"].get<std::string>() + "  x " +
                               fixed(s["position_mm"], 2) + " mm  F " + fixed(s["force_N"], 3) +
                               " N  IOP " + fixed(s["iop_mmHg"], 1) + " mmHg";
      if (line != last_line) std::cerr << "\r" << line << "   " << std::flush;
      last_line = line;
    }
    if (state == "Done" || state == "Fault" || state == "EStop" || state == "Ready" ||
        state == "Idle") {
      if (print_progress && !c.json()) std::cerr << "\n";
      std::signal(SIGINT, SIG_DFL);
      return s;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }
}

int run_cut(const CliContext& c, RunOptions& o, bool start) {
  proto::RunRequest& r = o.request;
  if (o.hold_s > 0) r.hold_s = o.hold_s;
  if (o.post_mortem_h >= 0) r.post_mortem_h = o.post_mortem_h;
  if (!o.operator_name.empty()) r.operator_ = o.operator_name;
  if (!o.notes.empty()) r.notes = o.notes;
  for (const auto& kv : o.meta) {
    const auto eq = kv.find('=');
    if (eq == std::string::npos) throw CLI::ValidationError("--meta " + kv, "expected key=value");
    if (!r.meta) r.meta.emplace();
    (*r.meta)[kv.substr(0, eq)] = kv.substr(eq + 1);
  }
  // A run asked for while the rig is still homing waits for the carriage to park, then starts.
  nlohmann::json before = parse_reply(c.client().get("/api/status"), "status");
  if (before["state"] == "Homing") {
    if (!c.json())
      std::cerr << "run: waiting for homing to finish (carriage at "
                << fixed(before["position_mm"], 2) << " mm)\n";
    if (!wait_while_homing(c, kHomingTimeout_s, before)) {
      std::cerr << "run: still homing after " << kHomingTimeout_s << " s; not started\n";
      return 1;
    }
  }
  const HttpReply reply =
      c.client().post(start ? "/api/run" : "/api/arm", nlohmann::json(r).dump());
  const nlohmann::json j = parse_reply(reply, "run");
  if (reply.status != 200) {
    std::cerr << "run: "
              << (j.contains("error") ? j["error"].get<std::string>()
                                      : j.value("result", "refused"))
              << "\n";
    if (c.json()) std::cout << j.dump() << "\n";
    return 1;
  }
  const std::int64_t run_id = j["run_id"];
  if (!c.json())
    std::cout << "run " << run_id << " armed (eye " << r.eye_id << ", IOP " << r.iop_mmHg
              << " mmHg, " << r.velocity_mm_s << " mm/s, " << r.depth_mm << " mm)\n";
  if (o.no_wait || !start) return 0;
  const nlohmann::json end = wait_for_run_end(c, true);
  if (end["state"] == "Fault" && !c.json())
    std::cerr << "run: the rig faulted: " << end["fault"].get<std::string>() << "\n";
  const nlohmann::json detail = archived_run_once_closed(c, run_id);
  if (c.json()) {
    std::cout << detail["run"].dump() << "\n";
  } else {
    const auto& run = detail["run"];
    std::cout << "run " << run_id << ": " << run["outcome"].get<std::string>()
              << (run.contains("reason") ? " (" + run["reason"].get<std::string>() + ")" : "")
              << ", " << run["samples"] << " samples archived\n";
  }
  return detail["run"]["outcome"] == "completed" ? 0 : 1;
}

}  // namespace

void add_control_commands(CLI::App& app, CliContext& c, int& exit_code) {
  app.add_subcommand("status", "state, interlocks, sensors and loop timing")->callback([&] {
    exit_code = show_status(c);
  });
  auto home_no_wait = std::make_shared<bool>(false);
  CLI::App* home =
      app.add_subcommand("home", "find the home switch and park the carriage; returns once parked");
  home->add_flag("--no-wait", *home_no_wait, "return as soon as homing has started");
  home->callback([&c, &exit_code, home_no_wait] { exit_code = home_rig(c, !*home_no_wait); });
  app.add_subcommand("tare", "zero the load cell (no load on the keratome); returns once tared")
      ->callback([&c, &exit_code] {
        exit_code = send_command(c, "tare");
        if (exit_code == 0 && !wait_until_tared(c)) exit_code = 1;
      });
  for (const auto& [name, help] : std::vector<std::pair<std::string, std::string>>{
           {"start", "start an armed run"},
           {"stop", "stop motion now; a running cut ends as 'stopped'"},
           {"estop", "software e-stop (latched until reset)"},
           {"reset", "leave Fault or EStop (home again afterwards)"}}) {
    app.add_subcommand(name, help)->callback([&c, &exit_code, n = name] {
      exit_code = send_command(c, n);
    });
  }
  CLI::App* runs = app.add_subcommand(
      "runs", "list the archived runs (pg:CONNINFO: every rig's, from the lab archive)");
  auto lab = add_lab_runs_options(runs);
  runs->callback(
      [&c, &exit_code, lab] { exit_code = lab->given() ? list_lab_runs(c, *lab) : list_runs(c); });
  auto options = std::make_shared<RunOptions>();
  for (const char* name : {"run", "arm"}) {
    const bool start = std::string(name) == "run";
    CLI::App* cmd = app.add_subcommand(
        name, start ? "set IOP, cut at constant velocity, retract; waits for the end"
                    : "set and settle the IOP, then wait for `rig start`");
    cmd->add_option("--iop", options->request.iop_mmHg, "IOP to hold [mmHg]")->required();
    cmd->add_option("--velocity", options->request.velocity_mm_s, "cutting velocity [mm/s]")
        ->required();
    cmd->add_option("--depth", options->request.depth_mm,
                    "insertion depth from the corneal surface [mm]")
        ->required();
    cmd->add_option("--eye", options->request.eye_id, "eye (specimen) id")->required();
    cmd->add_option("--hold", options->hold_s, "hold at depth before retracting [s]");
    cmd->add_option("--post-mortem", options->post_mortem_h, "hours since death");
    cmd->add_option("--operator", options->operator_name, "who runs the test");
    cmd->add_option("--notes", options->notes, "free text");
    cmd->add_option("--meta", options->meta, "more metadata: key=value (key with unit suffix)");
    cmd->add_flag("--no-wait", options->no_wait, "return once the run is armed");
    cmd->callback([&c, &exit_code, options, start] { exit_code = run_cut(c, *options, start); });
  }
}

}  // namespace rig::cli
