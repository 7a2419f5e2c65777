// The page's whole-run view of the archive (daemon/api/run_replay): every sample from a loop
// cycle, with the overlay's model, paged at a limit; query errors name the field.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <stdexcept>

#include "archive.hpp"
#include "frame_file.hpp"
#include "run_replay.hpp"
#include "test_paths.hpp"

namespace rig::api {
namespace {

constexpr double kSurfaceMm = 20.0;

// A recorded run: cycles 500..599 inserting 0.02 mm per cycle from 1 mm before the surface.
std::int64_t recorded_run(archive::Archive& a) {
  archive::NewRun run;
  run.eye_id = "E07";
  run.iop_mmHg = 15.0;
  run.surface_mm = kSurfaceMm;
  const std::int64_t id = a.create_run(run);
  a.mark_started(id);
  a.begin();
  for (std::uint64_t i = 0; i < 100; ++i) {
    rt::Sample s;
    s.run_id = id;
    s.cycle = 500 + i;
    s.t_s = 10.0 + static_cast<double>(i) * 1e-3;
    s.position_mm = kSurfaceMm - 1.0 + 0.02 * static_cast<double>(i);
    s.force_N = 0.001 * static_cast<double>(i);
    s.iop_mmHg = 15.0;
    s.phase = rt::CutPhase::kInsert;
    a.append_sample(s);
  }
  a.add_event(id, 10.05, "contact", "20.0");
  a.commit();
  a.finish_run(id, "completed", "");
  return id;
}

// A scratch archive holding the recorded run; stream(target) answers as GET target would.
class RunReplay : public ::testing::Test {
 protected:
  nlohmann::json stream(const std::string& target,
                        const std::shared_ptr<const model::ForceModel>& model = nullptr) {
    return nlohmann::json::parse(run_stream_json(archive_, id_, parse_replay_query(target), model));
  }
  rig::testing::ScratchDir dir_{"run-replay"};
  archive::Archive archive_{dir_.file("a.sqlite")};
  std::int64_t id_ = recorded_run(archive_);
};

TEST_F(RunReplay, TheStreamGivesEverySampleFromTheAskedCycleWithLoopTimeDepthAndEvents) {
  const auto j = stream("/api/runs/1/stream?from=550");
  ASSERT_EQ(j["cycle"].size(), 50U);
  EXPECT_EQ(j["cycle"][0], 550);
  EXPECT_EQ(j["cycle"][49], 599);
  EXPECT_EQ(j["next_cycle"], 600);
  EXPECT_FALSE(j["more"].get<bool>());
  EXPECT_NEAR(j["t_s"][0].get<double>(), 10.050, 1e-9);  // loop time, as the live stream has it
  EXPECT_NEAR(j["x_mm"][0].get<double>(), 0.0, 1e-9);    // from the corneal surface
  EXPECT_EQ(j["phase"][0], "insert");
  EXPECT_TRUE(j["model_N"][0].is_null());  // no model: nothing drawn, nothing made up
  EXPECT_EQ(j["outcome"], "completed");
  ASSERT_EQ(j["events"].size(), 1U);
  EXPECT_EQ(j["events"][0]["kind"], "contact");
}

TEST_F(RunReplay, ALimitPagesTheRunAndTheNextPageStartsWhereTheLastEnded) {
  const auto first = stream("x?from=0&limit=60");
  ASSERT_EQ(first["cycle"].size(), 60U);
  EXPECT_TRUE(first["more"].get<bool>());
  const std::string next =
      "x?limit=60&from=" + std::to_string(first["next_cycle"].get<std::int64_t>());
  const auto second = stream(next);
  ASSERT_EQ(second["cycle"].size(), 40U);
  EXPECT_EQ(second["cycle"][0], 560);
  EXPECT_FALSE(second["more"].get<bool>());
}

TEST_F(RunReplay, TheModelIsDrawnAtTheRunsIopAndTheResidualIsMeasuredMinusModel) {
  auto model = std::make_shared<const model::ForceModel>(
      model::ForceModel::load(testing::source("model/params/paper-interpreted.toml")));
  const auto j = stream("/api/runs/1/stream", model);
  ASSERT_EQ(j["cycle"].size(), 100U);
  for (std::size_t i = 0; i < 100; i += 33) {
    const double x = j["x_mm"][i].get<double>();
    EXPECT_NEAR(j["model_N"][i].get<double>(), model->baseline(x, 15.0), 1e-12);
    EXPECT_NEAR(j["residual_N"][i].get<double>(),
                j["force_N"][i].get<double>() - model->baseline(x, 15.0), 1e-12);
  }
}

TEST_F(RunReplay, BadQueriesAndUnknownRunsAreRefusedNamingWhat) {
  EXPECT_THROW(parse_replay_query("/s?from=abc"), std::invalid_argument);
  EXPECT_THROW(parse_replay_query("/s?from=-3"), std::invalid_argument);
  EXPECT_THROW(parse_replay_query("/s?limit=0"), std::invalid_argument);
  try {
    parse_replay_query("/s?from=12x");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'from'"), std::string::npos) << e.what();
  }
  EXPECT_EQ(parse_replay_query("/s").from_cycle, 0);
  EXPECT_THROW(run_stream_json(archive_, 42, ReplayQuery{}, nullptr), std::out_of_range);
  EXPECT_THROW(read_archived_frame(archive_, id_, 0), std::out_of_range);  // a run without frames
}

// Found by tests/fuzz/fuzz_archive_rows: a phase number the recorder never writes indexed
// the table of phase names out of bounds.
TEST_F(RunReplay, ASampleWhosePhaseIsNoCutPhaseIsRefusedNamingTheRunAndTheSample) {
  archive::Database db(archive_.path(), false);
  db.exec("UPDATE samples SET phase = 255 WHERE idx = 510");
  try {
    stream("/api/runs/1/stream?from=500");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "archive run 1: sample 510: phase 255 is not a cut phase (0..4)");
  }
  EXPECT_EQ(stream("/api/runs/1/stream?from=511")["cycle"].size(),
            89U);  // the samples after it replay
}

// Found by tests/fuzz/fuzz_archive_rows: the next cycle after the largest index overflowed
// (UBSan: signed integer overflow in ReplayColumns::write).
TEST_F(RunReplay, ASampleIndexThatIsNoLoopCycleIsRefusedNamingTheRun) {
  archive::Database db(archive_.path(), false);
  db.exec("UPDATE samples SET idx = 9223372036854775807 WHERE idx = 599");
  try {
    stream("/api/runs/1/stream?from=550&limit=100");
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(
        e.what(),
        "archive run 1: sample index 9223372036854775807 is not a loop cycle (0 .. 2^63-2)");
  }
  EXPECT_EQ(stream("/api/runs/1/stream?from=550&limit=49")["next_cycle"],
            599);  // the samples before it replay
}

std::string frame_error(archive::Archive& archive, std::int64_t run_id, std::int64_t frame_no) {
  try {
    read_archived_frame(archive, run_id, frame_no);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "no error";
}

// Found by tests/fuzz/fuzz_archive_rows: the row's size was allocated before reading, so a
// damaged row asked for a terabyte (ASan: allocation-size-too-big; without it, rigd's memory).
TEST_F(RunReplay, AFrameRowLargerThanItsFileIsRefusedBeforeAnyByteIsAllocatedNamingTheRunAndFrame) {
  const std::string file = dir_.file("run.frames");
  archive::FrameRow row;
  row.run_id = id_;
  row.sample_index = 510;
  row.file = file;
  row.width = row.height = 8;
  row.bytes = 64;
  row.file_offset =
      archive::FrameFile(file).append(std::vector<std::uint8_t>(64, 7));  // after its 16 B header
  archive_.add_frame(row);
  EXPECT_EQ(read_archived_frame(archive_, id_, 0).pixels, std::string(64, '\x07'));
  for (const std::int64_t bytes : {std::int64_t{1} << 40, std::int64_t{-5}, std::int64_t{65}}) {
    ++row.frame_no;
    row.bytes = bytes;
    archive_.add_frame(row);
  }
  EXPECT_EQ(frame_error(archive_, id_, 1),
            "archive run 1: frame 1: 1099511627776 B at offset 16 are not in its frame file " +
                file + " (80 B)");
  EXPECT_EQ(
      frame_error(archive_, id_, 2),
      "archive run 1: frame 2: -5 B at offset 16 are not in its frame file " + file + " (80 B)");
  EXPECT_EQ(
      frame_error(archive_, id_, 3),
      "archive run 1: frame 3: 65 B at offset 16 are not in its frame file " + file + " (80 B)");
  row.frame_no = 4, row.bytes = 1, row.file = "/dev/zero";
  archive_.add_frame(row);
  EXPECT_EQ(frame_error(archive_, id_, 4),
            "archive run 1: frame 4: 1 B at offset 16 are not in its frame file /dev/zero (0 B)");
}

}  // namespace
}  // namespace rig::api
