// Rows the product's writer never produces, put into an archive by hand (a damaged, edited or
// foreign archive; found by tests/fuzz/fuzz_archive_rows): every reader of runs returns data
// or refuses naming the run and what is wrong, never reads out of bounds.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <sstream>
#include <string>

#include "archive.hpp"
#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::archive {
namespace {

// A new archive at `path` holding one imported run of three samples with one channel of
// three values; returns the run's id.
std::int64_t archive_with_one_run(const std::string& path) {
  std::istringstream csv(
      "# eye_id: "
      "N1\nt_s,x_mm,force_N,iop_meas_mmHg\n0,0,0,15\n0.001,0.1,0.2,15\n0.002,0.2,0.4,15\n");
  Archive archive(path);
  return archive.import_run(model::read_run_csv(csv, "n1.csv"));
}

// Raw SQL on the archive file, as a hand edit or a foreign tool would do it.
void edit(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  char* error = nullptr;
  const int rc = sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error);
  const std::string message = error != nullptr ? error : "";
  sqlite3_free(error);
  sqlite3_close(db);
  ASSERT_EQ(rc, SQLITE_OK) << message;
}

std::string load_error(const std::string& path, std::int64_t run_id) {
  Archive archive(path, true);
  try {
    archive.load_run(run_id);
  } catch (const ArchiveError& e) {
    return e.what();
  }
  return "no error";
}

TEST(ArchiveDamagedRows, AChannelShorterThanTheSamplesIsRefusedNamingTheRunAndTheChannel) {
  testing::ScratchDir dir("archive-short-channel");
  const std::string path = dir.file("a.sqlite");
  const std::int64_t id = archive_with_one_run(path);
  // One double (8 bytes) for three samples: exporting it read past the channel's end.
  edit(path, "UPDATE channels SET data = zeroblob(8) WHERE run_id = " + std::to_string(id));
  EXPECT_EQ(load_error(path, id), "archive " + path + ": run " + std::to_string(id) +
                                      ": channel 'iop_meas_mmHg' has 1 values for 3 samples");
}

TEST(ArchiveDamagedRows, AChannelOfPartDoublesIsRefusedNamingItsSize) {
  testing::ScratchDir dir("archive-odd-channel");
  const std::string path = dir.file("a.sqlite");
  const std::int64_t id = archive_with_one_run(path);
  edit(path, "UPDATE channels SET data = zeroblob(27) WHERE run_id = " + std::to_string(id));
  EXPECT_EQ(load_error(path, id),
            "archive " + path + ": run " + std::to_string(id) +
                ": channel 'iop_meas_mmHg': 27 bytes are not a whole number of doubles");
}

TEST(ArchiveDamagedRows, AnEditedChannelOfTheRightLengthStillLoads) {
  testing::ScratchDir dir("archive-channel-ok");
  const std::string path = dir.file("a.sqlite");
  const std::int64_t id = archive_with_one_run(path);
  // A longer name moves the blob within its row: its doubles are copied out, not read in place.
  edit(path, "UPDATE channels SET name = 'iop_meas_mmHg_' WHERE run_id = " + std::to_string(id));
  Archive archive(path, true);
  const model::RunData run = archive.load_run(id);
  ASSERT_NE(run.channel("iop_meas_mmHg_"), nullptr);
  EXPECT_EQ(run.channel("iop_meas_mmHg_")->values, (std::vector<double>{15.0, 15.0, 15.0}));
}

}  // namespace
}  // namespace rig::archive
