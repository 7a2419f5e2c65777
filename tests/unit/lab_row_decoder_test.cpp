// Decoding what the lab archive's server sends (daemon/lab_archive/lab_row_decoder), on libpq
// results made without a server: bad values are refused naming the run, column and row
// (found by tests/fuzz/fuzz_lab_archive_rows).
#include <gtest/gtest.h>
#include <libpq-fe.h>

#include <optional>
#include <string>
#include <vector>

#include "lab_row_decoder.hpp"

namespace rig::lab_archive {
namespace {

using Row = std::vector<std::optional<std::string>>;

// A text-format result with these column names and rows (nullopt: SQL NULL).
PgResult result(const std::vector<std::string>& columns, const std::vector<Row>& rows) {
  PGresult* r = PQmakeEmptyPGresult(nullptr, PGRES_TUPLES_OK);
  std::vector<std::string> names = columns;
  std::vector<PGresAttDesc> attributes;
  for (auto& name : names) attributes.push_back({name.data(), 0, 0, 0, 25, -1, -1});
  PQsetResultAttrs(r, static_cast<int>(attributes.size()), attributes.data());
  for (std::size_t row = 0; row < rows.size(); ++row) {
    for (std::size_t c = 0; c < rows[row].size(); ++c) {
      const auto& v = rows[row][c];
      PQsetvalue(r, static_cast<int>(row), static_cast<int>(c),
                 v ? const_cast<char*>(v->c_str()) : nullptr, v ? static_cast<int>(v->size()) : -1);
    }
  }
  return PgResult(r);
}

// The metadata row of an imported run (source not "rig": its channels are its own).
PgResult imported_meta() {
  std::vector<std::string> columns;
  for (int c = 0; c < 19; ++c) columns.push_back("c" + std::to_string(c));
  Row row(19);
  row[0] = "N1", row[11] = "imported", row[13] = "n1.csv", row[14] = "0", row[15] = "4",
  row[16] = "rig07";
  row[17] = "u1", row[18] = std::string("lot\x1f") + "L3";
  return result(columns, {row});
}

PgResult three_samples() {
  return result({"t_s", "position_mm", "force_n", "iop_mmhg", "motor_v", "velocity_mm_s"},
                {{"0", "0", "0", std::nullopt, std::nullopt, std::nullopt},
                 {"0.001", "0.1", "0.2", std::nullopt, std::nullopt, std::nullopt},
                 {"0.002", "0.2", "0.4", std::nullopt, std::nullopt, std::nullopt}});
}

std::string decode_error(const PgResult& samples, const PgResult& channels) {
  try {
    decode_lab_run("u1", imported_meta(), samples, &channels);
  } catch (const LabArchiveError& e) {
    return e.what();
  }
  return "no error";
}

TEST(LabRowDecoder, AnImportedRunDecodesWithItsChannelsAndMetadata) {
  const PgResult channels = result({"name", "data"}, {{"iop_meas_mmHg", "15,NaN,-Infinity"}});
  const model::RunData run = decode_lab_run("u1", imported_meta(), three_samples(), &channels);
  ASSERT_EQ(run.size(), 3U);
  ASSERT_NE(run.channel("iop_meas_mmHg"), nullptr);
  EXPECT_EQ(run.channel("iop_meas_mmHg")->values.size(), 3U);
  EXPECT_EQ(run.text("lot"), "L3");
  EXPECT_EQ(run.text("eye_id"), "N1");
}

TEST(LabRowDecoder, AChannelShorterThanTheSamplesIsRefusedNamingTheRunAndTheChannel) {
  // array_to_string leaves NULL elements out: the run-CSV writer then read past the channel.
  const PgResult channels = result({"name", "data"}, {{"iop_meas_mmHg", "15"}});
  EXPECT_EQ(decode_error(three_samples(), channels),
            "lab archive: run u1: channel 'iop_meas_mmHg' has 1 values for 3 samples");
}

TEST(LabRowDecoder, AChannelValueThatIsNotANumberIsRefusedNamingTheRunTheChannelAndTheValue) {
  // std::stod threw std::invalid_argument("stod"), naming nothing.
  const PgResult channels =
      result({"name", "data"}, {{"iop_meas_mmHg", "15,,16"}, {"motor", "1,2x,3"}});
  EXPECT_EQ(decode_error(three_samples(), channels),
            "lab archive: run u1: channel 'iop_meas_mmHg': value 2 '' is not a number");
  const PgResult motor = result({"name", "data"}, {{"motor", "1,2x,3"}});
  EXPECT_EQ(decode_error(three_samples(), motor),
            "lab archive: run u1: channel 'motor': value 2 '2x' is not a number");
}

TEST(LabRowDecoder, AColumnThatIsNotANumberIsRefusedNamingTheColumnAndTheRow) {
  const PgResult samples =
      result({"t_s", "position_mm", "force_n", "iop_mmhg", "motor_v", "velocity_mm_s"},
             {{"0", "0", "0", "", "", ""}, {"0.001", "abc", "0", "", "", ""}});
  const PgResult no_channels = result({"name", "data"}, {});
  EXPECT_EQ(decode_error(samples, no_channels),
            "lab archive: run u1: samples: column 'position_mm' of row 1: 'abc' is not a number");
}

}  // namespace
}  // namespace rig::lab_archive
