// Haptic playback end to end: `rig haptic` as a process, and sessions inside rigd through
// its API (mesh frames on the WebSocket, one session at a time, the live rig as source).
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "command.hpp"
#include "rig_processes.hpp"
#include "ws_client.hpp"

namespace rig {
namespace {

using nlohmann::json;
using testing::run_command;
using Clock = std::chrono::steady_clock;

constexpr double kPaperRmseN = 0.004, kPaperMaxN = 0.016;  // haptic vs model, the paper's Omni
constexpr double kPaperVsExperimentRmseN = 0.005,
                 kPaperVsExperimentMaxN = 0.039;  // haptic vs measured

std::string rig_cli(const std::string& args) {
  return testing::bin("rig") + " " + args;
}

TEST(HapticCli, TheSimulatedPhantomPrintsTheDocumentedFiguresAndBeatsThePaper) {
  const auto result = run_command(
      rig_cli(
          "--format json haptic --device sim --source model --velocity 2 --iop 15 --virtual-time"),
      false);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const json j = json::parse(result.output);
  for (const char* key :
       {"rate_hz", "ticks", "overruns", "tick_p99_us", "rmse_vs_model_N", "max_vs_model_N",
        "rmse_vs_run_N", "max_vs_run_N", "mesh_vertices", "mesh_springs"}) {
    EXPECT_TRUE(j.contains(key)) << key;
  }
  EXPECT_LT(j["rmse_vs_model_N"].get<double>(), kPaperRmseN);
  EXPECT_LT(j["max_vs_model_N"].get<double>(), kPaperMaxN);
  EXPECT_TRUE(j["rmse_vs_run_N"].is_null()) << "no run to compare with was given";
  EXPECT_EQ(j["mesh_vertices"], 169);
  EXPECT_EQ(j["mesh_springs"], 886);
  EXPECT_GT(j["ticks"].get<int>(), 5000);
}

TEST(HapticCli, ARecordedRunFromTheArchiveIsFeltAndComparedWithTheRunAndTheModel) {
  testing::ScratchDir dir("haptic-run");
  ASSERT_EQ(run_command(rig_cli("sim generate --out " + dir.file("runs") +
                                " --iops 15 --velocities 2 --depth 8"))
                .exit_code,
            0);
  std::string files;
  for (const auto& f : std::filesystem::directory_iterator(dir.file("runs")))
    files += " " + f.path().string();
  const std::string archive = " --archive " + dir.file("archive.sqlite");
  ASSERT_EQ(run_command(rig_cli(archive + " import" + files)).exit_code, 0);
  const auto result = run_command(
      rig_cli("--format json" + archive + " haptic --source run:1 --virtual-time"), false);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const json j = json::parse(result.output);
  ASSERT_TRUE(j["rmse_vs_run_N"].is_number()) << j.dump();
  // Against a measured run the paper reports 5 mN / 39 mN. Our worst point is where the blade
  // turns back at its deepest: the measured release is steep (~0.5 N/mm) and after a reversal
  // the encoder cannot tell the new speed until its second count (0.055 mm).
  EXPECT_LT(j["rmse_vs_run_N"].get<double>(), kPaperVsExperimentRmseN);
  EXPECT_LT(j["max_vs_run_N"].get<double>(), kPaperVsExperimentMaxN);
  EXPECT_GT(j["rmse_vs_model_N"].get<double>(), 0.0);
}

TEST(HapticCli, APhantomWithoutOpenHapticsIsAClearErrorAndExitsNonZero) {
  const auto result =
      run_command(rig_cli("haptic --device phantom --source model --library /opt/none/libHD.so"));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("/opt/none/libHD.so"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("--device sim"), std::string::npos) << result.output;
  // Nothing else breaks: the simulated device still plays in the same installation.
  EXPECT_EQ(run_command(
                rig_cli("haptic --device sim --source model --virtual-time --velocity 4 --depth 2"))
                .exit_code,
            0);
}

TEST(HapticCli, ABadSourceIsRefusedNamingWhatIsAccepted) {
  const auto result = run_command(rig_cli("haptic --device sim --source modle --virtual-time"));
  EXPECT_NE(result.exit_code, 0);
  EXPECT_NE(result.output.find("modle"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("run:ID"), std::string::npos) << result.output;
}

json wait_haptic_done(const testing::RigProcesses& rig, double timeout_s) {
  const auto end = Clock::now() + std::chrono::duration<double>(timeout_s);
  json status;
  do {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    status = json::parse(rig.api().get("/api/haptic").body);
  } while (status["state"] == "running" && Clock::now() < end);
  return status;
}

TEST(RigdHaptics, ASessionStreamsTheCorneaAtThirtyHertzOrMoreAndRefusesASecondOne) {
  testing::ScratchDir dir("haptic-rigd");
  testing::RigProcesses rig(dir);
  testing::WsClient client(rig.url());
  const auto started =
      rig.api().post("/api/haptic", R"({"device":"sim","source":"model","velocity_mm_s":4})");
  ASSERT_EQ(started.status, 202) << started.body;
  EXPECT_EQ(rig.api().post("/api/haptic", R"({"device":"sim","source":"model"})").status, 409);
  std::size_t frames = 0;
  bool punctured = false;
  double first_t = -1.0, last_t = 0.0, deepest = 0.0;
  const auto end = Clock::now() + std::chrono::seconds(4);
  while (Clock::now() < end) {
    const json m = client.next();
    if (m["type"] != "mesh") continue;
    ++frames;
    EXPECT_EQ(m["x_mm"].size(), 13U);
    ASSERT_EQ(m["z_mm"].size(), 13U);
    punctured = punctured || m["punctured"].get<bool>();
    if (first_t < 0.0) first_t = m["t_s"];
    last_t = m["t_s"];
    for (const auto& z : m["z_mm"]) deepest = std::max(deepest, z.get<double>());
  }
  ASSERT_GT(frames, 10U);
  EXPECT_GE((frames - 1) / (last_t - first_t), 30.0)
      << frames << " frames over " << last_t - first_t << " s";
  EXPECT_TRUE(punctured) << "4 s at 4 mm/s go past the puncture";
  EXPECT_GT(deepest, 1.0) << "the tissue dents under the tip";
  const json done = wait_haptic_done(rig, 60);
  EXPECT_EQ(done["state"], "done") << done.dump();
  EXPECT_LT(done["rmse_vs_model_N"].get<double>(), kPaperRmseN);
  EXPECT_EQ(done["mesh_vertices"], 169);
}

TEST(RigdHaptics, ABadSourceOrAMissingPhantomIsRefusedWithTheReasonAndTheRigCarriesOn) {
  testing::ScratchDir dir("haptic-refused");
  testing::RigProcesses rig(dir);
  const auto bad = rig.api().post("/api/haptic", R"({"device":"sim","source":"modle"})");
  EXPECT_EQ(bad.status, 400);
  EXPECT_NE(bad.body.find("source"), std::string::npos) << bad.body;
  const auto phantom = rig.api().post("/api/haptic", R"({"device":"phantom","source":"model"})");
  EXPECT_EQ(phantom.status, 400);
  EXPECT_NE(phantom.body.find("libHD.so"), std::string::npos) << phantom.body;
  EXPECT_EQ(json::parse(rig.api().get("/api/haptic").body)["state"], "failed");
  const auto no_run = rig.api().post("/api/haptic", R"({"device":"sim","source":"run:999"})");
  EXPECT_EQ(no_run.status, 400);
  EXPECT_NE(no_run.body.find("999"), std::string::npos) << no_run.body;
  std::string why;
  EXPECT_TRUE(rig.prepare(why)) << why;  // the rig itself is unaffected
}

TEST(RigdHaptics, TheLiveRigIsFeltDuringACutAndMatchesTheModelWithinTheRigsOwnError) {
  testing::ScratchDir dir("haptic-live");
  testing::RigProcesses rig(dir);
  std::string why;
  json done;
  bool cut_done = false;
  // The subject is what the hand feels, not the loop's timing: a timing fault of the simulated
  // rig on a busy machine ends that cut, printed as ACCIDENTAL; the session and the cut start
  // again.
  for (int attempt = 0; attempt < 3; ++attempt) {
    ASSERT_TRUE(rig.prepare(why)) << why;
    const auto session =
        rig.api().post("/api/haptic", R"({"device":"sim","source":"live","max_s":12})");
    ASSERT_EQ(session.status, 202) << session.body;
    const auto run =
        rig.post_run(R"({"eye_id":"LIVE1","iop_mmHg":15,"velocity_mm_s":2,"depth_mm":6})");
    ASSERT_EQ(run.status, 200) << run.body;
    json last;
    ASSERT_TRUE(rig.wait(
        [&last](const json& s) {
          last = s;
          return s["state"] == "Done" || s["state"] == "Fault";
        },
        60))
        << rig.status().dump();
    done = wait_haptic_done(rig, 30);
    cut_done = last["state"] == "Done";
    if (cut_done) break;
    ASSERT_TRUE(cli::is_timing_fault(last.value("fault", ""))) << last.dump();
    std::printf("ACCIDENTAL | a timing fault while cutting, reset and cut again: %s\n",
                last.value("fault", "").c_str());
    rig.api().post("/api/reset");
    rig.wait([](const json& st) { return st["interlocks"]["link_ok"] == true; }, 10);
  }
  ASSERT_TRUE(cut_done) << "three cuts faulted on timing";
  EXPECT_EQ(done["state"], "done") << done.dump();
  EXPECT_GT(done["ticks"].get<int>(), 5000);
  // The simulated eye follows the model to ~2 mN; a dead feed (zero force) would be off by
  // the whole curve (peak 0.2 N, RMSE > 50 mN).
  EXPECT_LT(done["rmse_vs_model_N"].get<double>(), 0.02) << done.dump();
}

}  // namespace
}  // namespace rig
