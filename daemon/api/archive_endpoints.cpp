#include "archive_endpoints.hpp"

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>
#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <sstream>

#include "json_text.hpp"
#include "rig/proto/messages.hpp"
#include "run_csv.hpp"
#include "run_replay.hpp"
#include "sqlite_handle.hpp"

namespace rig::api {
namespace {

proto::RunSummary summary_of(const archive::RunRow& row) {
  proto::RunSummary s;
  s.run_id = row.id;
  s.eye_id = row.eye_id;
  s.iop_mmHg = row.iop_mmHg;
  s.velocity_mm_s = row.velocity_mm_s;
  s.depth_mm = row.depth_mm;
  s.started_at = row.started_at;
  if (!row.ended_at.empty()) s.ended_at = row.ended_at;
  s.outcome = row.outcome;
  if (!row.reason.empty()) s.reason = row.reason;
  s.samples = row.samples;
  s.source = row.source;
  return s;
}

Response csv_response(const Request& request, archive::Archive& archive, std::int64_t run_id) {
  std::ostringstream csv;
  model::write_run_csv(archive.load_run(run_id), csv);
  Response response = make_response(request, http::status::ok, csv.str(), "text/csv");
  response.set(http::field::content_disposition,
               "attachment; filename=\"run-" + std::to_string(run_id) + ".csv\"");
  response.prepare_payload();
  return response;
}

// The page's replay of an archived run, decimated to <= 5000 points.
Response samples_response(const Request& request, archive::Archive& archive, std::int64_t run_id) {
  const model::RunData run = archive.load_run(run_id);
  const std::size_t step = std::max<std::size_t>(1, run.size() / 5000);
  nlohmann::json j = {{"run_id", run_id},
                      {"t_s", nlohmann::json::array()},
                      {"x_mm", nlohmann::json::array()},
                      {"force_N", nlohmann::json::array()}};
  for (std::size_t i = 0; i < run.size(); i += step) {
    j["t_s"].push_back(run.t_s[i]);
    j["x_mm"].push_back(run.x_mm[i]);
    j["force_N"].push_back(run.force_N[i]);
  }
  return make_response(request, http::status::ok, json_text(j));
}

}  // namespace

ArchiveEndpoints::ArchiveEndpoints(boost::asio::io_context& io, ApiContext& context)
    : io_(&io), context_(&context) {
  // A whole-run export formats for seconds on this thread. On a loaded machine (2 cores)
  // the I/O thread, which answers stop and e-stop, must win the CPU over it: measured in
  // ApiSafety's export test under full load, e-stops then waited up to 600 ms for the CPU.
  boost::asio::post(pool_, [] {
    const auto thread_id = static_cast<id_t>(::syscall(SYS_gettid));
    if (::setpriority(PRIO_PROCESS, thread_id, kArchiveThreadNice) != 0) {
      spdlog::warn("api: cannot lower the archive thread's priority: {}", std::strerror(errno));
    }
  });
}

ArchiveEndpoints::~ArchiveEndpoints() {
  pool_.join();
}

archive::Archive& ArchiveEndpoints::archive() {
  if (!archive_) {
    archive_ = std::make_unique<archive::Archive>(context_->config->archive.path);
    archive_->defer_checkpoints();  // the recorder checkpoints between runs
  }
  return *archive_;
}

void ArchiveEndpoints::on_archive(const Request& request, Responder respond,
                                  std::function<Response(archive::Archive&)> work) {
  boost::asio::post(
      // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
      pool_, [this, request, respond = std::move(respond), work = std::move(work)]() mutable {
        Response response;
        try {
          response = work(archive());
        } catch (const archive::ArchiveError& e) {  // disk full, I/O error: say so, start nothing
          spdlog::error("api: {} {}: archive: {}", std::string(request.method_string()),
                        std::string(request.target()), e.what());
          response = error_response(request, http::status::insufficient_storage,
                                    std::string("archive cannot be written: ") + e.what());
        } catch (const std::exception& e) {
          spdlog::error("api: {} {}: {}", std::string(request.method_string()),
                        std::string(request.target()), e.what());
          response = error_response(request, http::status::internal_server_error, e.what());
        }
        boost::asio::post(*io_,
                          [respond = std::move(respond), response = std::move(response)]() mutable {
                            respond(std::move(response));
                          });
      });
}

void ArchiveEndpoints::get_runs(const Request& request, Responder respond) {
  // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
  on_archive(request, std::move(respond), [request](archive::Archive& a) {
    proto::RunList list;
    for (const auto& row : a.list_runs()) list.runs.push_back(summary_of(row));
    return make_response(request, http::status::ok, json_text(nlohmann::json(list)));
  });
}

void ArchiveEndpoints::get_run(const Request& request, std::int64_t run_id, const std::string& what,
                               Responder respond) {
  if (what == "/stream" || what.rfind("/frames/", 0) == 0)
    return get_replay(request, run_id, what, std::move(respond));
  // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
  on_archive(request, std::move(respond), [request, run_id, what](archive::Archive& a) {
    const auto row = a.find_run(run_id);
    if (!row)
      return error_response(request, http::status::not_found, "no run " + std::to_string(run_id));
    if (what == "/csv") return csv_response(request, a, run_id);
    if (what == "/samples") return samples_response(request, a, run_id);
    proto::RunDetail detail;
    detail.run = summary_of(*row);
    for (const auto& [k, v] : a.run_meta(run_id)) detail.meta[k] = v;
    for (const auto& e : a.run_events(run_id)) detail.events.push_back({e.t_s, e.kind, e.message});
    return make_response(request, http::status::ok, json_text(nlohmann::json(detail)));
  });
}

void ArchiveEndpoints::get_replay(const Request& request, std::int64_t run_id,
                                  const std::string& what, Responder respond) {
  ReplayQuery query;
  try {
    query = parse_replay_query(std::string(request.target()));
  } catch (const std::invalid_argument& e) {
    return respond(error_response(request, http::status::bad_request, e.what()));
  }
  auto model = context_->hub->model();  // drawn over the run as over the live stream
  on_archive(
      // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
      request, std::move(respond), [request, run_id, what, query, model](archive::Archive& a) {
        try {
          if (what == "/stream")
            return make_response(request, http::status::ok,
                                 run_stream_json(a, run_id, query, model));
          const FramePixels frame = read_archived_frame(a, run_id, std::stoll(what.substr(8)));
          Response response =
              make_response(request, http::status::ok, frame.pixels, "application/octet-stream");
          response.set("X-Frame-Width", std::to_string(frame.width));
          response.set("X-Frame-Height", std::to_string(frame.height));
          response.set("X-Frame-Sample", std::to_string(frame.sample_index));
          return response;
        } catch (const std::out_of_range& e) {
          return error_response(request, http::status::not_found, e.what());
        }
      });
}

void ArchiveEndpoints::create_run(const Request& request, archive::NewRun row,
                                  std::function<void(std::int64_t)> then, Responder respond) {
  // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
  boost::asio::post(pool_, [this, request, row = std::move(row), then = std::move(then),
                            respond = std::move(respond)]() mutable {
    try {
      const std::int64_t run_id = archive().create_run(row);
      boost::asio::post(*io_, [then = std::move(then), run_id] { then(run_id); });
    } catch (const std::exception& e) {
      spdlog::error("api: cannot create the run's row: {}", e.what());
      Response response = error_response(request, http::status::insufficient_storage,
                                         std::string("archive cannot be written: ") + e.what());
      boost::asio::post(*io_,
                        [respond = std::move(respond), response = std::move(response)]() mutable {
                          respond(std::move(response));
                        });
    }
  });
}

void ArchiveEndpoints::discard_refused_run(std::int64_t run_id, const std::string& why) {
  boost::asio::post(pool_, [this, run_id, why] {
    try {
      archive().discard_unstarted_run(run_id);
    } catch (const std::exception& e) {
      spdlog::error("api: run {} was refused ({}) and its row could not be removed: {}", run_id,
                    why, e.what());
    }
  });
}

}  // namespace rig::api
