#pragma once
// Rows in PostgreSQL's binary COPY format (COPY ... FROM STDIN WITH (FORMAT binary)): a
// signature header, per row the field count and per field its byte length and value in
// network byte order, and a trailer. The server stores the values as sent: no text to parse
// (about half of a text COPY's server CPU for the samples table), and doubles travel as their
// bit patterns (NaN, infinities and -0 included).
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace rig::lab_archive {

class BinaryCopyRows {
 public:
  BinaryCopyRows();
  // Starts a row of `fields` fields; every row of one COPY has the table's column count.
  void begin_row(std::int16_t fields);
  BinaryCopyRows& field(double value);  // float8
  BinaryCopyRows& field(const std::optional<double>& value);
  BinaryCopyRows& field(std::int64_t value);        // int8
  BinaryCopyRows& field_int16(std::int64_t value);  // int2 (throws outside -32768..32767)
  // uuid: its 16 bytes, from uuid_bytes() (parsed once for the many rows of one run).
  BinaryCopyRows& field_uuid(std::string_view bytes);
  // The 16 bytes of a uuid written "8-4-4-4-12" in hex; throws LabArchiveError if malformed.
  static std::string uuid_bytes(std::string_view text);
  // timestamptz: microseconds since 2000-01-01 00:00:00 UTC (PostgreSQL's epoch).
  BinaryCopyRows& field_timestamptz(std::int64_t microseconds_since_2000);
  BinaryCopyRows& null();
  std::int64_t rows() const { return rows_; }
  // Bytes not yet taken.
  std::size_t pending_bytes() const { return bytes_.size(); }
  // Appends the trailer: call once, after the last row.
  void finish();
  // The bytes since the last take (the header first), so a COPY goes out in pieces while
  // later rows are still being read; after finish() the last piece ends with the trailer.
  std::string take();

 private:
  void put16(std::uint16_t value);
  void put32(std::uint32_t value);
  void put64(std::uint64_t value);
  std::string bytes_;
  std::int64_t rows_ = 0;
  bool finished_ = false;
};

}  // namespace rig::lab_archive
