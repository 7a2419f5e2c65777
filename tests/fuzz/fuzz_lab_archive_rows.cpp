// libFuzzer target: rows the lab archive's PostgreSQL server sends back (issue 16, `pg:`
// sources), decoded without a server. The bytes become libpq results (PQmakeEmptyPGresult,
// text format, as the server's answers to LabRunReader's queries): the run list, one run's
// metadata row, its samples and its channels, every value NULL, any bytes, a value tens of
// KB long, or text PostgreSQL prints for numbers, arrays and the joined metadata (NaN,
// -Infinity, 1e+300, "1,,2", "k\x1fv\x1e..."). The decoders (lab_row_decoder.hpp) must give
// run data whose channels match its samples, or refuse with LabArchiveError.
// A finding is a memory error, UB, a leak, an exception that is not a runtime_error with a
// message, or run data whose columns or channels differ in length.
#include <libpq-fe.h>

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "fuzz_byte_reader.hpp"
#include "fuzz_run_checks.hpp"
#include "lab_row_decoder.hpp"

namespace {

using rig::fuzz::FuzzByteReader;
using rig::lab_archive::PgResult;

// The server's text for a value: the first byte picks the kind; nullopt is SQL NULL.
std::optional<std::string> server_text(FuzzByteReader& in) {
  static const char* const kTexts[] = {"",
                                       "0",
                                       "1.5",
                                       "-2",
                                       "NaN",
                                       "Infinity",
                                       "-Infinity",
                                       "1e+300",
                                       "1e400",
                                       "12abc",
                                       "-",
                                       " 7",
                                       "0x1p3",
                                       "9223372036854775808",
                                       "-9223372036854775809",
                                       "rig",
                                       "imported",
                                       "2026-11-24T10:00:00.000Z",
                                       "k\x1fv",
                                       "k\x1fv\x1ek2\x1fv2\x1e",
                                       "\x1e\x1f\x1e",
                                       "1,2,3",
                                       ",",
                                       "1,,2",
                                       "1,NaN,-Infinity,1e+300",
                                       "3,"};
  switch (in.below(6)) {
    case 0:
      return std::nullopt;
    case 1:
      return std::string(kTexts[in.below(std::size(kTexts))]);
    case 2:
      return in.bytes();
    case 3:
      return in.stretched(16 * 1024);
    case 4: {  // a list of numbers, as array_to_string(float8[], ',') prints one
      std::string list;
      const std::size_t count = in.byte();
      for (std::size_t i = 0; i < count; ++i)
        list += (i > 0 ? "," : "") + std::to_string(static_cast<int>(in.byte()) - 100);
      return list;
    }
    default:
      return std::to_string(static_cast<int>(in.byte()) - 8);
  }
}

// A result of `columns` columns and `rows` rows; each row's values are fuzzed, and rows past
// `distinct` repeat the last fuzzed one (many rows from few bytes).
PgResult make_result(FuzzByteReader& in, int columns, int rows, int distinct) {
  PGresult* result = PQmakeEmptyPGresult(nullptr, PGRES_TUPLES_OK);
  std::vector<std::string> names(static_cast<std::size_t>(columns));
  std::vector<PGresAttDesc> attributes(static_cast<std::size_t>(columns));
  for (int c = 0; c < columns; ++c) {
    names[static_cast<std::size_t>(c)] = "c" + std::to_string(c);
    attributes[static_cast<std::size_t>(c)] = {
        names[static_cast<std::size_t>(c)].data(), 0, 0, 0, 25, -1, -1};  // text
  }
  PQsetResultAttrs(result, columns, attributes.data());
  std::vector<std::optional<std::string>> row(static_cast<std::size_t>(columns));
  for (int r = 0; r < rows; ++r) {
    if (r < distinct) {
      for (auto& value : row) value = server_text(in);
    }
    for (int c = 0; c < columns; ++c) {
      const auto& value = row[static_cast<std::size_t>(c)];
      PQsetvalue(result, r, c, value ? const_cast<char*>(value->data()) : nullptr,
                 value ? static_cast<int>(value->size()) : -1);
    }
  }
  return PgResult(result);
}

int row_count(FuzzByteReader& in) {
  const int rows = in.below(8);
  return rows < 7 ? rows : 7 + static_cast<int>(in.byte()) * 4;  // up to ~1,000 rows
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzByteReader in(data, size);
  const std::string uuid = "0b7e1c5e-0000-4000-8000-00000000000" + std::to_string(in.below(10));
  const int listed = in.below(4);
  const PgResult list = make_result(in, 13, listed, listed);
  for (int r = 0; r < listed; ++r) {
    rig::fuzz::refusal_allowed("run list row",
                               [&] { (void)rig::lab_archive::decode_run_row(list, r); });
  }
  const PgResult meta = make_result(in, 19, in.below(5) == 0 ? 0 : 1, 1);
  const int samples_rows = row_count(in);
  const PgResult samples = make_result(in, 6, samples_rows, 1 + in.below(6));
  const int channel_rows = in.below(4);
  const PgResult channels = make_result(in, 2, channel_rows, channel_rows);
  rig::fuzz::refusal_allowed("run " + uuid, [&] {
    const bool from_rig = rig::lab_archive::lab_run_from_rig(meta, uuid);
    const rig::model::RunData run =
        rig::lab_archive::decode_lab_run(uuid, meta, samples, from_rig ? nullptr : &channels);
    rig::fuzz::check_columns(run, "run " + uuid);
    rig::fuzz::export_and_read_back(run, "run " + uuid);
  });
  (void)rig::lab_archive::split_extra_meta(in.bytes());
  return 0;
}
