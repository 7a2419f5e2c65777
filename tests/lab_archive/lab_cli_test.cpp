// The `rig` command line on the lab archive (a throwaway PostgreSQL 15): three rigs' archives
// pushed into one server, then listed, exported and diagnosed together with pg: sources,
// giving what the same runs give from their files. Runs the built `rig`: label lab.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <signal.h>

#include <filesystem>

#include "archive.hpp"
#include "child_process.hpp"
#include "command.hpp"
#include "pg_test_server.hpp"
#include "test_paths.hpp"

namespace rig::lab_archive {
namespace {

using nlohmann::json;

class LabCli : public ::testing::Test {
 protected:
  testing::CommandResult rig(const std::string& args) {
    return testing::run_command(testing::bin("rig") + " " + args);
  }
  std::string pg() const { return "'pg:" + server_.conninfo() + "'"; }
  // Simulated runs (one CSV each), imported into `rigs` archives in turn and pushed.
  std::vector<std::string> three_rigs_pushed() {
    EXPECT_EQ(rig("sim generate --out " + dir_.file("runs") +
                  " --effect shaft_friction --iops 15,18 --velocities 2,3 --depth 8 --hold 0.5")
                  .exit_code,
              0);
    std::vector<std::string> files;
    for (const auto& e : std::filesystem::directory_iterator(dir_.file("runs")))
      files.push_back(e.path().string());
    std::sort(files.begin(), files.end());
    const std::vector<std::string> rigs = {"rig-a", "rig-b", "rig-c"};
    for (std::size_t i = 0; i < files.size(); ++i) {
      const std::string archive = dir_.file(rigs[i % 3] + ".sqlite");
      EXPECT_EQ(rig("--archive " + archive + " import " + files[i]).exit_code, 0);
    }
    for (const auto& name : rigs) {
      const auto pushed = rig("--archive " + dir_.file(name + ".sqlite") + " lab-archive push " +
                              pg() + " --rig-id " + name + " --sslmode disable");
      EXPECT_EQ(pushed.exit_code, 0) << pushed.output;
    }
    return files;
  }
  testing::ScratchDir dir_{"lab-cli"};
  testing::PgTestServer server_;
};

TEST_F(LabCli, RunsOfThreeRigsAreListedFilteredAndDiagnosedTogetherAsFromTheirFiles) {
  const auto files = three_rigs_pushed();
  const json all = json::parse(rig("--format json runs " + pg()).output);
  ASSERT_EQ(all["runs"].size(), files.size());
  const json of_b = json::parse(rig("--format json runs " + pg() + " --rig rig-b").output);
  EXPECT_EQ(of_b["runs"].size(), (files.size() + 1) / 3);
  EXPECT_EQ(
      json::parse(rig("--format json runs " + pg() + " rig=rig-c since=2000-01-01").output)["runs"]
          .size(),
      files.size() / 3);
  const auto from_pg =
      rig("--format json model diagnose " + pg() + " --only shaft_friction,sensor_drift");
  const auto from_files = rig("--format json model diagnose " + dir_.file("runs") +
                              " --only shaft_friction,sensor_drift");
  ASSERT_EQ(from_pg.exit_code, 0) << from_pg.output;
  ASSERT_EQ(from_files.exit_code, 0) << from_files.output;
  const json a = json::parse(from_pg.output.substr(from_pg.output.find('{')));
  const json b = json::parse(from_files.output.substr(from_files.output.find('{')));
  EXPECT_EQ(a["verdict"], b["verdict"]);
  EXPECT_EQ(a["candidates"], b["candidates"]);
}

TEST_F(LabCli, OneRunExportsAsTheRunCsvItWasImportedFrom) {
  const auto files = three_rigs_pushed();
  const json runs = json::parse(rig("--format json runs " + pg() + " rig=rig-a").output);
  const std::string uuid = runs["runs"][0]["run_uuid"];
  const auto exported =
      rig("export " + pg() + " run=" + uuid + " --csv -o " + dir_.file("back.csv"));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  const auto local = rig("--archive " + dir_.file("rig-a.sqlite") + " export 1 --csv -o " +
                         dir_.file("local.csv"));
  ASSERT_EQ(local.exit_code, 0) << local.output;
  // Same samples and channels: the data lines after the header agree, metadata aside.
  const auto data = [](const std::string& file) {
    return testing::run_command("grep -v '^#' " + file).output;
  };
  EXPECT_EQ(data(dir_.file("back.csv")), data(dir_.file("local.csv")));
  std::filesystem::create_directories(dir_.file("all"));
  ASSERT_EQ(rig("export " + pg() + " --eye-lot none -o " + dir_.file("all")).exit_code,
            1);  // nothing matches: an error
  ASSERT_EQ(rig("export " + pg() + " -o " + dir_.file("all")).exit_code, 0);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir_.file("all")),
                          std::filesystem::directory_iterator{}),
            static_cast<long>(files.size()));
}

TEST_F(LabCli, APushKilledMidTransferResumesWithoutDuplicates) {
  archive::Archive local(dir_.file("big.sqlite"));
  model::RunData run;
  run.meta = {{"eye_id", "K1"}};
  for (int i = 0; i < 50000; ++i) {
    run.t_s.push_back(i * 1e-3);
    run.x_mm.push_back(i * 1e-5);
    run.force_N.push_back(1e-3 * (i % 1000));
  }
  for (int r = 0; r < 4; ++r) local.import_run(run);
  const std::vector<std::string> push = {
      testing::bin("rig"), "--archive", dir_.file("big.sqlite"),
      "lab-archive",       "push",      "pg:" + server_.conninfo(),
      "--rig-id",          "rig-k",     "--sslmode",
      "disable",           "--batch",   "5000"};
  cli::ChildProcess first(push, dir_.file("push1.log"));
  auto shipped = [this] {
    try {
      return std::stol(server_.query("SELECT coalesce(sum(samples), 0) FROM runs"));
    } catch (const std::runtime_error&) {
      return 0L;  // the push has not made the schema yet
    }
  };
  for (int i = 0; i < 400 && shipped() == 0; ++i) usleep(25000);
  kill(first.pid(), SIGKILL);
  usleep(200000);
  const long shipped_before = std::stol(server_.query("SELECT count(*) FROM samples"));
  EXPECT_GT(shipped_before, 0);
  EXPECT_LT(shipped_before, 200000) << "the push finished before it was killed: nothing was tested";
  std::string again;
  for (const auto& arg : push) again += "'" + arg + "' ";
  const auto second = testing::run_command(again);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(server_.query("SELECT count(*) || ' ' || count(DISTINCT (run_uuid, idx)) FROM samples"),
            "200000 200000");
  EXPECT_EQ(server_.query("SELECT string_agg(samples::text, ',') FROM runs"),
            "50000,50000,50000,50000");
}

}  // namespace
}  // namespace rig::lab_archive
