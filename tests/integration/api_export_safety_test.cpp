// E-stop during a large export (issue 14), rigd + rig-sim as processes: a 1,000,000-sample run
// is exported as CSV while an e-stop is sent every 20 ms; each must be answered 200 within
// 100 ms. Label load (./rig stress, not ./rig test): on this 2-core VM under load a few of
// 160-280 e-stops took 190-250 ms (ASan) while the export formatted the CSV; the cause is open
// (docs/api.md), so this test is the load tier's, where it fails today.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <string>
#include <thread>
#include <vector>

#include "archive.hpp"
#include "http_probe.hpp"
#include "long_run.hpp"
#include "rig_processes.hpp"
#include "safety_answers.hpp"

namespace rig {
namespace {

using boost::beast::http::verb;
using Clock = std::chrono::steady_clock;
using testing::expect_each_answered_in_time;

model::RunData long_run(std::size_t samples) {
  return testing::long_run(samples, 1e-3);
}  // [s] apart

// Lines of a run-CSV that are neither metadata ("# key: value") nor the column header.
std::size_t sample_lines(const std::string& csv) {
  std::size_t lines = 0;
  for (std::size_t at = 0; at < csv.size();) {
    const std::size_t end = std::min(csv.find('\n', at), csv.size());
    if (csv[at] != '#') ++lines;
    at = end + 1;
  }
  return lines == 0 ? 0 : lines - 1;
}

TEST(ApiSafety, EveryEStopIsAnsweredWithin100msWhileALargeRunIsExportedAsCsv) {
  testing::ScratchDir dir("api-safety-export");
  constexpr std::size_t kSamples = 1'000'000;  // ~17 min at 1 kHz: seconds to read and format
  std::int64_t run_id = 0;
  {
    archive::Archive archive(dir.file("archive.sqlite"));  // RigProcesses' archive path
    run_id = archive.import_run(long_run(kSamples));
  }
  testing::RigProcesses rig(dir);
  const int port = testing::port_of(rig.url());

  std::atomic<bool> exporting{true};
  cli::HttpReply csv;
  double export_s = 0.0;
  std::thread exporter([&] {
    const auto start = Clock::now();
    csv = rig.api().get("/api/runs/" + std::to_string(run_id) + "/csv");
    export_s = std::chrono::duration<double>(Clock::now() - start).count();
    exporting.store(false);
  });
  std::vector<testing::ProbeReply> estops;
  while (exporting.load()) {
    estops.push_back(testing::http_probe(port, verb::post, "/api/estop"));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  exporter.join();
  std::printf("export of %zu samples: %.2f s, %zu bytes\n", kSamples, export_s, csv.body.size());
  EXPECT_EQ(csv.status, 200) << csv.body.substr(0, 300);
  EXPECT_EQ(sample_lines(csv.body), kSamples) << "every sample exported";
  EXPECT_GE(estops.size(), 5U) << "the export lasted long enough to e-stop during it";
  expect_each_answered_in_time(estops, "e-stop during a large export");
}

}  // namespace
}  // namespace rig
