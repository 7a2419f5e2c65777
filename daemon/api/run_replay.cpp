#include "run_replay.hpp"

#include <nlohmann/json.hpp>

#include <charconv>
#include <filesystem>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "json_text.hpp"
#include "replay_columns.hpp"
#include "run_types.hpp"
#include "sqlite_handle.hpp"

namespace rig::api {
namespace {

std::int64_t query_integer(const std::string& query, const std::string& name,
                           std::int64_t fallback) {
  const std::string key = name + "=";
  std::size_t at = 0;
  while (at < query.size()) {
    const std::size_t end = std::min(query.find('&', at), query.size());
    if (query.compare(at, key.size(), key) == 0) {
      const char* first = query.data() + at + key.size();
      const char* last = query.data() + end;
      std::int64_t value = 0;
      const auto [ptr, ec] = std::from_chars(first, last, value);
      if (ec != std::errc() || ptr != last || value < 0) {
        throw std::invalid_argument("query field '" + name +
                                    "' must be a non-negative integer, not '" +
                                    std::string(first, last) + "'");
      }
      return value;
    }
    at = end + 1;
  }
  return fallback;
}

struct RunInfo {
  double surface_mm = 0.0;
  double iop_mmHg = 15.0;
};

RunInfo run_info(archive::Database& db, std::int64_t run_id) {
  archive::Statement q = db.prepare("SELECT surface_mm, iop_mmHg FROM runs WHERE id = ?");
  q.bind(1, run_id);
  RunInfo info;
  if (q.step()) {
    info.surface_mm = q.real(0);
    info.iop_mmHg = q.maybe_real(1).value_or(15.0);
  }
  return info;
}

// A sample's phase as the recorder writes it (rt::CutPhase): any other number in the archive
// is refused, naming the run and the sample (the phase names are a table indexed by it).
rt::CutPhase phase_of(std::int64_t phase, std::int64_t run_id, std::int64_t idx) {
  if (phase < 0 || phase > static_cast<std::int64_t>(rt::CutPhase::kRetract)) {
    throw std::runtime_error("archive run " + std::to_string(run_id) + ": sample " +
                             std::to_string(idx) + ": phase " + std::to_string(phase) +
                             " is not a cut phase (0..4)");
  }
  return static_cast<rt::CutPhase>(phase);
}

// A sample's index as the recorder writes it (its loop cycle, >= 0 by the query); the page
// asks for the cycle after the last, so the largest integer is refused, naming the run.
std::int64_t cycle_of(std::int64_t idx, std::int64_t run_id) {
  if (idx == std::numeric_limits<std::int64_t>::max()) {
    throw std::runtime_error("archive run " + std::to_string(run_id) + ": sample index " +
                             std::to_string(idx) + " is not a loop cycle (0 .. 2^63-2)");
  }
  return idx;
}

// Samples from the cycle on, column-wise as in the live SampleBatch.
void add_samples(nlohmann::json& j, archive::Database& db, std::int64_t run_id,
                 const ReplayQuery& query, const std::shared_ptr<const model::ForceModel>& model) {
  const RunInfo info = run_info(db, run_id);
  archive::Statement q = db.prepare(
      "SELECT idx, t_s, position_mm, force_N, iop_mmHg, phase FROM samples WHERE run_id = ? AND "
      "idx >= ? ORDER BY idx LIMIT ?");
  q.bind(1, run_id).bind(2, query.from_cycle).bind(3, query.limit + 1);
  ReplayColumns columns(model, info.surface_mm, info.iop_mmHg);
  bool more = false;
  while (q.step()) {
    if (static_cast<std::int64_t>(columns.size()) == query.limit) {
      more = true;
      break;
    }
    columns.add(cycle_of(q.integer(0), run_id), q.real(1), q.real(2), q.real(3),
                q.maybe_real(4).value_or(std::numeric_limits<double>::quiet_NaN()),
                phase_of(q.integer(5), run_id, q.integer(0)));
  }
  columns.write(j, query.from_cycle, more);
}

}  // namespace

ReplayQuery parse_replay_query(const std::string& target) {
  const std::size_t q = target.find('?');
  ReplayQuery query;
  if (q == std::string::npos) return query;
  const std::string text = target.substr(q + 1);
  query.from_cycle = query_integer(text, "from", 0);
  query.limit = query_integer(text, "limit", query.limit);
  if (query.limit < 1 || query.limit > 1000000)
    throw std::invalid_argument("query field 'limit' must be 1..1000000");
  return query;
}

std::string run_stream_json(archive::Archive& archive, std::int64_t run_id,
                            const ReplayQuery& query,
                            const std::shared_ptr<const model::ForceModel>& model) {
  const auto row = archive.find_run(run_id);
  if (!row) throw std::out_of_range("no run " + std::to_string(run_id));
  nlohmann::json j = {
      {"type", "run_stream"},          {"run_id", run_id},
      {"eye_id", row->eye_id},         {"outcome", row->outcome},
      {"reason", row->reason},         {"source", row->source},
      {"started_at", row->started_at}, {"model", model ? model->name : std::string()}};
  archive::Database db(archive.path(),
                       true);  // a reader of its own: the recorder writes meanwhile (WAL)
  add_samples(j, db, run_id, query, model);
  nlohmann::json events = nlohmann::json::array();
  for (const auto& e : archive.run_events(run_id))
    events.push_back({{"t_s", e.t_s}, {"kind", e.kind}, {"message", e.message}});
  j["events"] = std::move(events);
  nlohmann::json frames = nlohmann::json::array();
  for (const auto& f : archive.run_frames(run_id)) {
    if (f.sample_index >= 0)
      frames.push_back({{"frame_no", f.frame_no}, {"sample_index", f.sample_index}});
  }
  j["frames"] = std::move(frames);
  return json_text(j);
}

namespace {

// The frame's bytes must lie in its file (a regular file) before any is allocated or read:
// the archive's row holds the size, and a damaged row asked for terabytes (or /dev/zero).
void require_frame_in_file(const archive::FrameRow& f) {
  std::error_code ec;
  const std::uintmax_t file_bytes =
      std::filesystem::is_regular_file(f.file, ec) ? std::filesystem::file_size(f.file, ec) : 0;
  const bool inside = !ec && f.bytes >= 0 && f.file_offset >= 0 &&
                      static_cast<std::uintmax_t>(f.file_offset) <= file_bytes &&
                      static_cast<std::uintmax_t>(f.bytes) <=
                          file_bytes - static_cast<std::uintmax_t>(f.file_offset);
  if (!inside) {
    throw std::runtime_error(
        "archive run " + std::to_string(f.run_id) + ": frame " + std::to_string(f.frame_no) + ": " +
        std::to_string(f.bytes) + " B at offset " + std::to_string(f.file_offset) +
        " are not in its frame file " + f.file + " (" + std::to_string(file_bytes) + " B)");
  }
}

}  // namespace

FramePixels read_archived_frame(archive::Archive& archive, std::int64_t run_id,
                                std::int64_t frame_no) {
  for (const auto& f : archive.run_frames(run_id)) {
    if (f.frame_no != frame_no) continue;
    require_frame_in_file(f);
    FramePixels out{f.width, f.height, f.sample_index,
                    std::string(static_cast<std::size_t>(f.bytes), '\0')};
    std::ifstream in(f.file, std::ios::binary);
    in.seekg(f.file_offset);
    if (!in.read(out.pixels.data(), f.bytes))
      throw std::runtime_error("frame file " + f.file + ": cannot read frame " +
                               std::to_string(frame_no));
    return out;
  }
  throw std::out_of_range("run " + std::to_string(run_id) + " has no frame " +
                          std::to_string(frame_no));
}

}  // namespace rig::api
