// The run-CSV interchange format: round trip, and errors that name the file and line.
#include <gtest/gtest.h>

#include <sstream>

#include "run_csv.hpp"
#include "test_paths.hpp"

namespace rig::model {
namespace {

std::string error_for(const std::string& text) {
  std::istringstream in(text);
  try {
    read_run_csv(in, "bad.csv");
  } catch (const RunCsvError& e) {
    return e.what();
  }
  return "no error";
}

TEST(RunCsv, ReadsMetadataColumnsAndExtraChannels) {
  std::istringstream in(
      "# eye_id: E07\n# iop_mmHg: 15\n# velocity_mm_s: 2.0\n# operator: technician-3\n# "
      "future_key_C: 21.5\n"
      "t_s,x_mm,force_N,temperature_C\r\n0.0,0.0,0.0003,21.4\r\n0.001,0.002,0.0002,21.5\r\n");
  const RunData run = read_run_csv(in, "ok.csv");
  ASSERT_EQ(run.size(), 2U);
  EXPECT_EQ(run.text("eye_id"), "E07");
  EXPECT_EQ(run.number("iop_mmHg"), 15.0);
  EXPECT_FALSE(run.number("operator").has_value());  // text, not a covariate
  EXPECT_EQ(run.number("future_key_C"), 21.5);       // unknown keys are kept
  ASSERT_EQ(run.channels.size(), 1U);
  EXPECT_EQ(run.channels[0].name, "temperature_C");
  EXPECT_DOUBLE_EQ(run.channels[0].values[1], 21.5);
  EXPECT_TRUE(run.warnings.empty());
}

TEST(RunCsv, ColumnsMayComeInAnyOrder) {
  std::istringstream in("force_N,t_s,x_mm\n0.1,0.0,0.5\n");
  const RunData run = read_run_csv(in, "order.csv");
  EXPECT_DOUBLE_EQ(run.force_N[0], 0.1);
  EXPECT_DOUBLE_EQ(run.x_mm[0], 0.5);
}

TEST(RunCsv, MissingIopOrVelocityIsAWarningNotAnError) {
  std::istringstream in("t_s,x_mm,force_N\n0,0,0\n");
  const RunData run = read_run_csv(in, "warn.csv");
  ASSERT_EQ(run.warnings.size(), 2U);
  EXPECT_NE(run.warnings[0].find("iop_mmHg"), std::string::npos);
}

TEST(RunCsv, AnUnparsableRowNamesFileLineAndColumn) {
  const std::string m = error_for("# iop_mmHg: 15\nt_s,x_mm,force_N\n0,0,0\n0.001,abc,0\n");
  EXPECT_EQ(m, "bad.csv:4: column 'x_mm': 'abc' is not a number");
}

TEST(RunCsv, AShortRowIsAnError) {
  EXPECT_EQ(error_for("t_s,x_mm,force_N\n0,0\n"), "bad.csv:2: expected 3 fields, found 2");
}

TEST(RunCsv, TimeGoingBackwardsIsAnError) {
  EXPECT_NE(error_for("t_s,x_mm,force_N\n0.2,0,0\n0.1,0,0\n")
                .find("bad.csv:3: column 't_s': time goes backwards"),
            std::string::npos);
}

TEST(RunCsv, AMissingRequiredColumnIsNamed) {
  EXPECT_EQ(error_for("t_s,x_mm\n0,0\n"),
            "bad.csv:1: required column 'force_N' is missing from the header");
}

TEST(RunCsv, NonFiniteNumbersAreRejected) {
  EXPECT_NE(error_for("t_s,x_mm,force_N\n0,0,nan\n").find("'force_N': 'nan' is not a number"),
            std::string::npos);
}

TEST(RunCsv, AMalformedMetadataLineIsAnError) {
  EXPECT_EQ(error_for("# just a comment\nt_s,x_mm,force_N\n0,0,0\n"),
            "bad.csv:1: metadata line is not '# key: value'");
}

TEST(RunCsv, WritingAndReadingGivesTheSameRun) {
  RunData run;
  run.meta = {{"eye_id", "E1"}, {"iop_mmHg", "16"}, {"velocity_mm_s", "2"}};
  run.t_s = {0.0, 0.001, 0.002};
  run.x_mm = {-0.5, 0.0, 0.002};
  run.force_N = {0.0, 0.001, 0.0015};
  run.channels.push_back({"iop_meas_mmHg", {16.0, 16.1, 15.9}});
  std::stringstream text;
  write_run_csv(run, text);
  const RunData back = read_run_csv(text, "round.csv");
  EXPECT_EQ(back.meta, run.meta);
  EXPECT_EQ(back.x_mm, run.x_mm);
  EXPECT_EQ(back.force_N, run.force_N);
  EXPECT_EQ(back.channels[0].values, run.channels[0].values);
}

TEST(RunCsv, NotesWithNewlinesAndBackslashesSurviveTheRoundTrip) {
  RunData run;
  run.meta = {{"eye_id", "E2"},
              {"notes", "blade chipped\nre-run on E3\r\nC:\\data\\e2 and a literal \\n"}};
  run.t_s = {0.0, 0.001};
  run.x_mm = {0.0, 0.002};
  run.force_N = {0.0, 0.001};
  std::stringstream text;
  write_run_csv(run, text);
  const std::string written = text.str();
  const std::string notes_line =
      written.substr(written.find("# notes: "), written.find("re-run") - written.find("# notes: "));
  EXPECT_EQ(notes_line.find('\n'), std::string::npos) << "the notes stay on their metadata line:\n"
                                                      << written;
  const RunData back = read_run_csv(text, "notes.csv");
  EXPECT_EQ(back.meta, run.meta);
  EXPECT_EQ(back.size(), 2U);
}

TEST(RunCsv, AVeryLongMetadataLineIsReadWithoutRecursion) {
  const std::string value(2'000'000, 'a');
  std::istringstream in("# notes: " + value + "\n# iop_mmHg: 15\nt_s,x_mm,force_N\n0,0,0\n");
  const RunData run = read_run_csv(in, "long.csv");
  EXPECT_EQ(run.text("notes")->size(), value.size());
  EXPECT_EQ(error_for("# 9key: 1\nt_s,x_mm,force_N\n0,0,0\n"),
            "bad.csv:1: metadata line is not '# key: value'");
  EXPECT_EQ(error_for("# key value\nt_s,x_mm,force_N\n0,0,0\n"),
            "bad.csv:1: metadata line is not '# key: value'");
}

TEST(RunCsv, TheDigitisedNeedleDataImports) {
  const RunData run = read_run_csv(
      testing::source("tests/data/okamura2004-needle/needle-liver-insert-hold-retract.csv"));
  EXPECT_GT(run.size(), 800U);
  EXPECT_EQ(run.number("velocity_mm_s"), 10.0);
  EXPECT_EQ(run.warnings.size(), 1U);  // no IOP: a liver has none
}

}  // namespace
}  // namespace rig::model
