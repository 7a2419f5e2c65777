#include "lab_run_replay.hpp"

#include <nlohmann/json.hpp>

#include <limits>
#include <regex>
#include <stdexcept>

#include "json_text.hpp"
#include "lab_run_reader.hpp"
#include "pg_connection.hpp"
#include "replay_columns.hpp"
#include "run_types.hpp"

namespace rig::api {
namespace {

int query_hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

// application/x-www-form-urlencoded: %XX and '+' for a space; a broken escape is an error.
std::string query_text_decoded(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '+') {
      out += ' ';
    } else if (text[i] != '%') {
      out += text[i];
    } else {
      const int high = i + 2 < text.size() ? query_hex_value(text[i + 1]) : -1;
      const int low = high >= 0 ? query_hex_value(text[i + 2]) : -1;
      if (low < 0)
        throw std::invalid_argument("query '" + text + "': a '%' not followed by two hex digits");
      out += static_cast<char>(high * 16 + low);
      i += 2;
    }
  }
  return out;
}

// NOLINTNEXTLINE(bugprone-exception-escape): its implicit move (clang-tidy 14)
struct LabRunInfo {
  nlohmann::json header;
  double surface_mm = 0.0;
  double iop_mmHg = 15.0;
};

LabRunInfo run_info(lab_archive::PgConnection& db, const std::string& uuid) {
  const lab_archive::PgResult q = db.query(
      "SELECT eye_id, outcome, coalesce(reason, ''), source, rig_id, local_run_id, surface_mm, "
      "iop_mmhg, "
      "to_char(coalesce(started_at, created_at) AT TIME ZONE 'UTC', "
      "'YYYY-MM-DD\"T\"HH24:MI:SS.MS\"Z\"') "
      "FROM runs WHERE run_uuid = $1",
      {uuid}, "read run " + uuid);
  if (q.rows() == 0) throw std::out_of_range("the lab archive has no run " + uuid);
  LabRunInfo info;
  info.header = {{"type", "run_stream"},
                 {"run_id", 0},
                 {"run_uuid", uuid},
                 {"eye_id", q.text(0, 0)},
                 {"outcome", q.text(0, 1)},
                 {"reason", q.text(0, 2)},
                 {"source", q.text(0, 3)},
                 {"rig_id", q.text(0, 4)},
                 {"local_run_id", q.integer(0, 5)},
                 {"started_at", q.text(0, 8)}};
  info.surface_mm = q.real(0, 6);
  info.iop_mmHg = q.is_null(0, 7) ? 15.0 : q.real(0, 7);
  return info;
}

// Samples from the index on, column-wise as in run_replay's add_samples.
void add_samples(nlohmann::json& j, lab_archive::PgConnection& db, const std::string& uuid,
                 const LabRunInfo& info, const ReplayQuery& query,
                 const std::shared_ptr<const model::ForceModel>& model) {
  const lab_archive::PgResult q = db.query(
      "SELECT idx, t_s, position_mm, force_n, iop_mmhg, phase FROM samples WHERE run_uuid = $1 AND "
      "idx >= $2 "
      "ORDER BY idx LIMIT $3",
      {uuid, std::to_string(query.from_cycle), std::to_string(query.limit + 1)},
      "read samples of " + uuid);
  const int rows = std::min<int>(q.rows(), static_cast<int>(query.limit));
  ReplayColumns columns(model, info.surface_mm, info.iop_mmHg);
  for (int r = 0; r < rows; ++r) {
    const auto phase =
        q.is_null(r, 5) ? rt::CutPhase::kNone : static_cast<rt::CutPhase>(q.integer(r, 5));
    columns.add(q.integer(r, 0), q.real(r, 1), q.real(r, 2), q.real(r, 3),
                q.is_null(r, 4) ? std::numeric_limits<double>::quiet_NaN() : q.real(r, 4), phase);
  }
  columns.write(j, query.from_cycle, q.rows() > rows);
}

}  // namespace

std::vector<std::string> parse_lab_run_filters(const std::string& target) {
  std::vector<std::string> filters;
  const std::size_t q = target.find('?');
  if (q == std::string::npos) return filters;
  const std::string text = target.substr(q + 1);
  for (std::size_t at = 0; at < text.size();) {
    const std::size_t end = std::min(text.find('&', at), text.size());
    const std::string pair = text.substr(at, end - at);
    at = end + 1;
    if (pair.empty()) continue;
    const std::size_t eq = pair.find('=');
    if (eq == std::string::npos || eq == 0)
      throw std::invalid_argument("query field '" + pair + "' is not key=value");
    filters.push_back(query_text_decoded(pair.substr(0, eq)) + "=" +
                      query_text_decoded(pair.substr(eq + 1)));
  }
  return filters;
}

std::string lab_run_list_json(lab_archive::LabRunReader& reader,
                              const std::vector<std::string>& filters, std::size_t newest) {
  lab_archive::LabRunFilter filter;
  for (const std::string& f : filters) filter.add(f);
  const std::vector<lab_archive::LabRunRow> rows = reader.list_runs(filter);
  nlohmann::json runs = nlohmann::json::array();
  for (std::size_t i = rows.size() > newest ? rows.size() - newest : 0; i < rows.size(); ++i) {
    const lab_archive::LabRunRow& r = rows[i];
    runs.push_back({{"run_uuid", r.uuid},
                    {"rig_id", r.rig_id},
                    {"local_run_id", r.local_run_id},
                    {"eye_id", r.eye_id},
                    {"eye_lot", r.eye_lot},
                    {"started_at", r.started_at},
                    {"outcome", r.outcome},
                    {"samples", r.samples}});
  }
  return json_text(nlohmann::json{{"runs", std::move(runs)}, {"total", rows.size()}});
}

std::string lab_run_stream_json(lab_archive::LabRunReader& reader, const std::string& run_uuid,
                                const ReplayQuery& query,
                                const std::shared_ptr<const model::ForceModel>& model) {
  static const std::regex kUuid(
      "^[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}$");
  if (!std::regex_match(run_uuid, kUuid))
    throw std::invalid_argument("'" + run_uuid + "' is not a run uuid");
  lab_archive::PgConnection& db = reader.connection();
  const LabRunInfo info = run_info(db, run_uuid);
  nlohmann::json j = info.header;
  j["model"] = model ? model->name : std::string();
  add_samples(j, db, run_uuid, info, query, model);
  const lab_archive::PgResult ev =
      db.query("SELECT t_s, kind, message FROM events WHERE run_uuid = $1 ORDER BY seq", {run_uuid},
               "read events of " + run_uuid);
  nlohmann::json events = nlohmann::json::array();
  for (int r = 0; r < ev.rows(); ++r)
    events.push_back({{"t_s", ev.real(r, 0)}, {"kind", ev.text(r, 1)}, {"message", ev.text(r, 2)}});
  j["events"] = std::move(events);
  j["frames"] = nlohmann::json::array();
  return json_text(j);
}

}  // namespace rig::api
