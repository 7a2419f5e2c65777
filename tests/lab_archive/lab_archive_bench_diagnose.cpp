// bench-lab-archive, second part: the same runs read by `rig model diagnose` from the lab
// archive (PostgreSQL) and from a rig's SQLite archive; and the bare load time of each.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <string>

#include "archive.hpp"
#include "command.hpp"
#include "lab_run_reader.hpp"
#include "pg_test_server.hpp"
#include "test_paths.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// IOPs x velocities giving at least `runs` simulated runs (shallow cuts: the load, not the
// simulation, is measured).
std::string generate_command(const std::string& out, int runs) {
  std::string iops, velocities;
  const int n_iop = 25;
  const int n_velocity = (runs + n_iop - 1) / n_iop;
  for (int i = 0; i < n_iop; ++i) iops += (i ? "," : "") + std::to_string(10 + i);
  for (int v = 0; v < n_velocity; ++v)
    velocities +=
        (v ? "," : "") + std::to_string(1.0 + 3.0 * v / std::max(1, n_velocity)).substr(0, 5);
  return rig::testing::bin("rig") + " sim generate --out " + out + " --iops " + iops +
         " --velocities " + velocities + " --depth 4 --hold 0";
}

void run_or_throw(const std::string& command) {
  const auto r = rig::testing::run_command(command);
  if (r.exit_code != 0) {
    throw std::runtime_error(command.substr(0, 300) + " failed:\n" +
                             r.output.substr(r.output.size() > 2000 ? r.output.size() - 2000 : 0));
  }
}

}  // namespace

int diagnose_phase(int runs, rig::testing::PgTestServer& server,
                   const rig::testing::ScratchDir& dir) {
  const std::string out = dir.file("runs");
  const std::string sqlite = dir.file("diagnose.sqlite");
  run_or_throw(generate_command(out, runs));
  run_or_throw(rig::testing::bin("rig") + " --archive " + sqlite + " import " + out + "/*.csv");
  const auto push_start = Clock::now();
  run_or_throw(rig::testing::bin("rig") + " --archive " + sqlite + " lab-archive push 'pg:" +
               server.conninfo() + "' --rig-id bench-diagnose --sslmode disable");
  const double push_s = seconds_since(push_start);
  rig::archive::Archive archive(sqlite, true);
  const auto rows = archive.list_runs();
  std::size_t samples = 0;
  auto start = Clock::now();
  for (const auto& row : rows) samples += archive.load_run(row.id).size();
  const double load_sqlite = seconds_since(start);
  rig::lab_archive::LabRunReader reader(server.conninfo());
  start = Clock::now();
  for (const auto& row : reader.list_runs({})) reader.load_run(row.uuid);
  const double load_pg = seconds_since(start);
  std::string ids;
  for (const auto& row : rows) ids += " " + std::to_string(row.id);
  const std::string diagnose = rig::testing::bin("rig") + " model diagnose ";
  start = Clock::now();
  run_or_throw(diagnose + ids.substr(1) + " --archive " + sqlite + " --only shaft_friction");
  const double diagnose_sqlite = seconds_since(start);
  start = Clock::now();
  run_or_throw(diagnose + "'pg:" + server.conninfo() +
               "' --rig bench-diagnose --only shaft_friction");
  const double diagnose_pg = seconds_since(start);
  std::printf("diagnose: %zu runs, %zu samples (pushed in %.1f s)\n", rows.size(), samples, push_s);
  std::printf("  load only:              SQLite %.2f s, PostgreSQL %.2f s\n", load_sqlite, load_pg);
  std::printf("  rig model diagnose --only shaft_friction: SQLite %.1f s, PostgreSQL %.1f s\n",
              diagnose_sqlite, diagnose_pg);
  return 0;
}
