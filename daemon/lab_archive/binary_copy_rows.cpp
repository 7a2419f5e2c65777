#include "binary_copy_rows.hpp"

#include <bit>

#include "pg_connection.hpp"

namespace rig::lab_archive {
namespace {

// "PGCOPY\n\377\r\n\0", then flags (32 bits, 0: no OIDs) and header extension length (32 bits, 0).
constexpr char kHeader[] = "PGCOPY\n\377\r\n\0\0\0\0\0\0\0\0\0";
constexpr std::size_t kHeaderBytes = 11 + 4 + 4;

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

BinaryCopyRows::BinaryCopyRows() {
  bytes_.assign(kHeader, kHeaderBytes);
}

void BinaryCopyRows::put16(std::uint16_t value) {
  const char raw[2] = {static_cast<char>(value >> 8), static_cast<char>(value)};
  bytes_.append(raw, sizeof raw);
}

void BinaryCopyRows::put32(std::uint32_t value) {
  char raw[4];
  for (int i = 0; i < 4; ++i) raw[i] = static_cast<char>(value >> (24 - 8 * i));
  bytes_.append(raw, sizeof raw);
}

void BinaryCopyRows::put64(std::uint64_t value) {
  char raw[8];
  for (int i = 0; i < 8; ++i) raw[i] = static_cast<char>(value >> (56 - 8 * i));
  bytes_.append(raw, sizeof raw);
}

void BinaryCopyRows::begin_row(std::int16_t fields) {
  put16(static_cast<std::uint16_t>(fields));
  ++rows_;
}

BinaryCopyRows& BinaryCopyRows::field(double value) {
  put32(8);
  put64(std::bit_cast<std::uint64_t>(value));
  return *this;
}

BinaryCopyRows& BinaryCopyRows::field(const std::optional<double>& value) {
  return value ? field(*value) : null();
}

BinaryCopyRows& BinaryCopyRows::field(std::int64_t value) {
  put32(8);
  put64(static_cast<std::uint64_t>(value));
  return *this;
}

BinaryCopyRows& BinaryCopyRows::field_int16(std::int64_t value) {
  if (value < -32768 || value > 32767) {
    throw LabArchiveError("lab archive: " + std::to_string(value) +
                          " does not fit a smallint column");
  }
  put32(2);
  put16(static_cast<std::uint16_t>(static_cast<std::int16_t>(value)));
  return *this;
}

std::string BinaryCopyRows::uuid_bytes(std::string_view text) {
  constexpr std::size_t kBytes = 16;
  std::string raw;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '-' && (i == 8 || i == 13 || i == 18 || i == 23)) continue;
    const int high = hex_digit(text[i]);
    const int low = i + 1 < text.size() ? hex_digit(text[i + 1]) : -1;
    if (high < 0 || low < 0 || raw.size() == kBytes)
      throw LabArchiveError("lab archive: '" + std::string(text) + "' is not a UUID");
    raw += static_cast<char>(high * 16 + low);
    ++i;
  }
  if (raw.size() != kBytes)
    throw LabArchiveError("lab archive: '" + std::string(text) + "' is not a UUID");
  return raw;
}

BinaryCopyRows& BinaryCopyRows::field_uuid(std::string_view bytes) {
  put32(static_cast<std::uint32_t>(bytes.size()));
  bytes_.append(bytes);
  return *this;
}

BinaryCopyRows& BinaryCopyRows::field_timestamptz(std::int64_t microseconds_since_2000) {
  return field(microseconds_since_2000);
}

BinaryCopyRows& BinaryCopyRows::null() {
  put32(0xFFFFFFFFU);  // length -1
  return *this;
}

void BinaryCopyRows::finish() {
  if (!finished_) put16(0xFFFFU);  // field count -1: the end of the data
  finished_ = true;
}

std::string BinaryCopyRows::take() {
  std::string piece;
  piece.swap(bytes_);
  return piece;
}

}  // namespace rig::lab_archive
