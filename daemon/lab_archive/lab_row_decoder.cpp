#include "lab_row_decoder.hpp"

#include <cstdlib>
#include <sstream>
#include <string_view>

#include "metadata_number.hpp"

namespace rig::lab_archive {
namespace {

std::optional<double> maybe_real(const PgResult& rows, int row, int column) {
  if (rows.is_null(row, column)) return std::nullopt;
  return rows.real(row, column);
}

// The runs columns that are metadata, in the metadata query's order (0..13).
std::vector<std::pair<std::string, std::string>> column_meta(const PgResult& q) {
  const char* names[] = {
      "eye_id",        "iop_mmHg", "velocity_mm_s", "depth_mm",    "hold_s",
      "post_mortem_h", "operator", "notes",         "config_hash", "software_version",
      "started_at",    "outcome",  "reason",        "source"};
  std::vector<std::pair<std::string, std::string>> meta;
  for (int i = 0; i < 14; ++i) {
    if (q.is_null(0, i)) continue;
    const bool numeric = i >= 1 && i <= 5;
    std::string value = numeric ? archive::metadata_number_text(q.real(0, i)) : q.text(0, i);
    if (!value.empty()) meta.emplace_back(names[i], value);
  }
  meta.emplace_back("run_id", q.text(0, 15));
  meta.emplace_back("rig_id", q.text(0, 16));
  meta.emplace_back("run_uuid", q.text(0, 17));
  for (auto& pair : split_extra_meta(q.text(0, 18))) meta.push_back(std::move(pair));
  return meta;
}

void decode_samples(const PgResult& q, double surface_mm, bool from_rig, model::RunData& run) {
  const int n = q.rows();
  const double t0 = from_rig && n > 0 ? q.real(0, 0) : 0.0;
  model::Channel iop{"iop_meas_mmHg", {}}, motor{"motor_cmd_V", {}},
      velocity{"velocity_meas_mm_s", {}};
  for (int r = 0; r < n; ++r) {
    run.t_s.push_back(q.real(r, 0) - t0);
    run.x_mm.push_back(q.real(r, 1) - surface_mm);
    run.force_N.push_back(q.real(r, 2));
    if (!from_rig) continue;
    iop.values.push_back(q.real(r, 3));
    motor.values.push_back(q.real(r, 4));
    velocity.values.push_back(q.real(r, 5));
  }
  if (from_rig) run.channels = {std::move(iop), std::move(motor), std::move(velocity)};
}

// array_to_string(data, ','): PostgreSQL's float8 text ("1.5", "NaN", "-Infinity", "1e+300").
model::Channel decode_channel(const PgResult& ch, int row, const std::string& run_uuid) {
  model::Channel channel{ch.text(row, 0), {}};
  std::istringstream values(ch.text(row, 1));
  for (std::string value; std::getline(values, value, ',');) {
    char* end = nullptr;
    const double number = std::strtod(value.c_str(), &end);
    if (value.empty() || end != value.c_str() + value.size()) {
      throw LabArchiveError("lab archive: run " + run_uuid + ": channel '" + channel.name +
                            "': value " + std::to_string(channel.values.size() + 1) + " '" +
                            value.substr(0, 40) + "' is not a number");
    }
    channel.values.push_back(number);
  }
  return channel;
}

// Runs decode(); a value it refuses is refused naming the run and the part of it too.
template <typename Decode>
auto naming_run(const std::string& run_uuid, const char* part, Decode decode) {
  try {
    return decode();
  } catch (const LabArchiveError& e) {
    constexpr std::string_view kPrefix = "lab archive: ";
    std::string what = e.what();
    if (what.rfind(kPrefix, 0) == 0) what.erase(0, kPrefix.size());
    throw LabArchiveError(std::string(kPrefix) + "run " + run_uuid + ": " + part + ": " + what);
  }
}

}  // namespace

LabRunRow decode_run_row(const PgResult& rows, int r) {
  return {rows.text(r, 0),        rows.text(r, 1),        rows.integer(r, 2),
          rows.text(r, 3),        rows.text(r, 4),        maybe_real(rows, r, 5),
          maybe_real(rows, r, 6), maybe_real(rows, r, 7), rows.text(r, 8),
          rows.text(r, 9),        rows.text(r, 10),       rows.text(r, 11),
          rows.integer(r, 12)};
}

bool lab_run_from_rig(const PgResult& meta, const std::string& run_uuid) {
  if (meta.rows() == 0) throw LabArchiveError("lab archive: no run " + run_uuid);
  return meta.text(0, 13) == "rig";
}

model::RunData decode_lab_run(const std::string& run_uuid, const PgResult& meta,
                              const PgResult& samples, const PgResult* channels) {
  model::RunData run;
  run.source = "lab archive run " + run_uuid;
  const bool from_rig = lab_run_from_rig(meta, run_uuid);
  run.meta = naming_run(run_uuid, "metadata", [&meta] { return column_meta(meta); });
  const double surface_mm = naming_run(run_uuid, "metadata", [&meta] { return meta.real(0, 14); });
  naming_run(run_uuid, "samples", [&] { decode_samples(samples, surface_mm, from_rig, run); });
  if (!from_rig && channels != nullptr) {
    for (int r = 0; r < channels->rows(); ++r)
      run.channels.push_back(decode_channel(*channels, r, run_uuid));
  }
  if (const auto mismatch = run.channel_length_mismatch())
    throw LabArchiveError("lab archive: run " + run_uuid + ": " + *mismatch);
  return run;
}

std::vector<std::pair<std::string, std::string>> split_extra_meta(const std::string& joined) {
  std::vector<std::pair<std::string, std::string>> meta;
  std::istringstream extra(joined);
  for (std::string pair; std::getline(extra, pair, '\x1e');) {
    const auto cut = pair.find('\x1f');
    if (cut != std::string::npos) meta.emplace_back(pair.substr(0, cut), pair.substr(cut + 1));
  }
  return meta;
}

}  // namespace rig::lab_archive
