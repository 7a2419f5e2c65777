// PostgreSQL's binary COPY format as BinaryCopyRows writes it (no server: the bytes
// themselves; tests/lab_archive/lab_replication_test.cpp sends them to a real one).
#include <gtest/gtest.h>

#include <limits>

#include "binary_copy_rows.hpp"
#include "pg_connection.hpp"

namespace rig::lab_archive {
namespace {

std::string bytes(std::initializer_list<int> values) {
  std::string out;
  for (const int v : values) out += static_cast<char>(v);
  return out;
}

TEST(BinaryCopyRows, APayloadIsTheSignatureRowsInNetworkByteOrderAndTheTrailer) {
  BinaryCopyRows rows;
  rows.begin_row(4);
  rows.field(std::int64_t{258}).field(-2.0).field_int16(-2).null();
  rows.finish();
  const std::string payload = rows.take();
  const std::string expected =
      std::string("PGCOPY\n\377\r\n\0", 11) + std::string(8, '\0') + bytes({0, 4}) +
      bytes({0, 0, 0, 8, 0, 0, 0, 0, 0, 0, 1, 2}) +                        // int8 258
      bytes({0, 0, 0, 8, 0xC0, 0, 0, 0, 0, 0, 0, 0}) +                     // float8 -2
      bytes({0, 0, 0, 2, 0xFF, 0xFE}) + bytes({0xFF, 0xFF, 0xFF, 0xFF}) +  // int2 -2, NULL
      bytes({0xFF, 0xFF});                                                 // trailer
  EXPECT_EQ(payload, expected);
  EXPECT_EQ(rows.rows(), 1);
  EXPECT_EQ(rows.pending_bytes(), 0U);
}

TEST(BinaryCopyRows, PiecesTakenAlongTheWayJoinIntoTheSamePayload) {
  BinaryCopyRows whole, pieces;
  std::string joined;
  for (int row = 0; row < 3; ++row) {
    for (BinaryCopyRows* rows : {&whole, &pieces}) {
      rows->begin_row(1);
      rows->field(std::numeric_limits<double>::quiet_NaN());
    }
    joined += pieces.take();
  }
  whole.finish();
  pieces.finish();
  joined += pieces.take();
  EXPECT_EQ(joined, whole.take());
}

TEST(BinaryCopyRows, AUuidIsItsSixteenBytesAndAMalformedOneIsRefused) {
  EXPECT_EQ(BinaryCopyRows::uuid_bytes("00112233-4455-6677-8899-aAbBcCdDeEfF"),
            bytes({0x00, 0x11, 0x22, 0x33, 0x44, 0x55, 0x66, 0x77, 0x88, 0x99, 0xAA, 0xBB, 0xCC,
                   0xDD, 0xEE, 0xFF}));
  for (const char* bad :
       {"", "00112233-4455-6677-8899-aabbccddeef", "00112233-4455-6677-8899-aabbccddeeff0",
        "0011223-34455-6677-8899-aabbccddeeff", "00112233-4455-6677-8899-aabbccddeefg"}) {
    EXPECT_THROW(BinaryCopyRows::uuid_bytes(bad), LabArchiveError) << bad;
  }
}

TEST(BinaryCopyRows, ASmallintOutOfRangeIsRefusedNotWrapped) {
  BinaryCopyRows rows;
  rows.begin_row(2);
  rows.field_int16(32767).field_int16(-32768);
  EXPECT_THROW(rows.field_int16(32768), LabArchiveError);
  EXPECT_THROW(rows.field_int16(-32769), LabArchiveError);
}

}  // namespace
}  // namespace rig::lab_archive
