// rigd: the rig's real-time daemon.
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/sinks/systemd_sink.h>
#include <spdlog/spdlog.h>
#include <CLI/CLI.hpp>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <iostream>

#include "rig/config/config_error.hpp"
#include "rig/config/rigd_config.hpp"
#include "rigd_app.hpp"
#include "systemd_notifier.hpp"
#include "watchdog_feeder.hpp"

namespace {

void setup_logging() {
  // Under systemd (JOURNAL_STREAM set) log straight to the journal with priorities.
  if (std::getenv("JOURNAL_STREAM") != nullptr) {
    spdlog::set_default_logger(std::make_shared<spdlog::logger>(
        "rigd", std::make_shared<spdlog::sinks::systemd_sink_st>()));
  } else {
    spdlog::set_default_logger(spdlog::stderr_color_mt("rigd"));
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %v");
  }
}

// Signals are taken by sigwait in main, never by the RT thread (blocked before any thread starts).
sigset_t block_shutdown_signals() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, nullptr);
  // A full disk may show up as RLIMIT_FSIZE: a failed write is handled, not a killed daemon.
  std::signal(SIGXFSZ, SIG_IGN);
  return signals;
}

}  // namespace

static int run_rigd(int argc, char** argv) {
  CLI::App app{"rigd: real-time daemon of the keratome incision rig"};
  std::string config_path = "/etc/rigd/rigd.toml";
  std::vector<std::string> overrides;
  bool check_only = false;
  bool print_keys = false;
  app.add_option("--config", config_path, "TOML config file");
  app.add_option("--set", overrides, "override a config key: key=value (TOML value)");
  app.add_flag("--check-config", check_only, "validate the config and exit");
  app.add_flag("--print-config-keys", print_keys, "list every config key with its range and unit");
  CLI11_PARSE(app, argc, argv);
  if (print_keys) {
    std::cout << rig::config::describe_config_keys();
    return 0;
  }
  setup_logging();
  rig::config::RigdConfig config;
  try {
    config = rig::config::load_rigd_config(config_path, overrides);
  } catch (const rig::config::ConfigError& e) {
    std::cerr << "rigd: config error: " << e.what() << "\n";
    return 2;
  }
  if (check_only) {
    std::cout << "rigd: " << config_path << " is valid (hash " << config.hash << ")\n";
    return 0;
  }
  const sigset_t signals = block_shutdown_signals();
  const rig::service::SystemdNotifier notifier;
  notifier.status("starting: drivers, RT loop, API");
  rig::service::RigdApp rigd(config);
  try {
    rigd.start();
  } catch (const std::exception& e) {
    spdlog::critical("cannot start: {}", e.what());
    std::cerr << "rigd: cannot start: " << e.what() << "\n";
    return 1;
  }
  const std::string where = "http://" + config.api.bind + ":" + std::to_string(rigd.api_port());
  std::cout << "rigd: ready, API on " << where << std::endl;
  notifier.ready("RT loop at " + std::to_string(static_cast<int>(config.loop.rate_hz)) +
                 " Hz, API on " + where);
  rig::service::WatchdogFeeder feeder(
      rig::service::SystemdNotifier::watchdog_interval(), [&rigd] { return rigd.loop_alive(); },
      [&notifier] { notifier.watchdog(); },
      [&notifier](const std::string& text) {
        notifier.status(text);
        spdlog::critical("{}", text);
      });
  feeder.start();
  int signal = 0;
  sigwait(&signals, &signal);
  spdlog::info("signal {}: shutting down", signal);
  notifier.stopping();
  feeder.stop();
  rigd.shutdown();
  return 0;
}

// An exception no command caught (a bug, or a resource gone at setup) ends the program with its
// message and status 1, not with std::terminate's abort.
int main(int argc, char** argv) {
  try {
    return run_rigd(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "rigd: error: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "rigd: error: an unknown exception\n");
  }
  return 1;
}
