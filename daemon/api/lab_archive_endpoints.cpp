#include "lab_archive_endpoints.hpp"

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>

#include <stdexcept>

#include "lab_run_reader.hpp"
#include "lab_run_replay.hpp"
#include "pg_connection.hpp"
#include "stream_hub.hpp"

namespace rig::api {
namespace {

constexpr std::size_t kPickerRuns = 500;  // the newest runs the picker lists

}  // namespace

LabArchiveEndpoints::LabArchiveEndpoints(boost::asio::io_context& io, ApiContext& context)
    : io_(&io), context_(&context) {}

LabArchiveEndpoints::~LabArchiveEndpoints() {
  pool_.join();
}

void LabArchiveEndpoints::on_pool(const Request& request, Responder respond, Work work) {
  if (context_->lab_archive_connection.empty()) {
    return respond(
        error_response(request, http::status::service_unavailable,
                       "the lab archive is off on this rig ([lab_archive] enabled = false)"));
  }
  auto connection = context_->lab_archive_connection;
  // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
  boost::asio::post(pool_, [this, request, respond = std::move(respond), work = std::move(work),
                            connection]() mutable {
    Response response;
    try {
      response = make_response(request, http::status::ok, work(connection));
    } catch (const std::invalid_argument& e) {
      response = error_response(request, http::status::bad_request, e.what());
    } catch (const std::out_of_range& e) {
      response = error_response(request, http::status::not_found, e.what());
    } catch (const std::exception& e) {  // the server is down or refuses us: say so
      spdlog::warn("api: {}: {}", std::string(request.target()), e.what());
      response = error_response(request, http::status::bad_gateway, e.what());
    }
    boost::asio::post(*io_,
                      [respond = std::move(respond), response = std::move(response)]() mutable {
                        respond(std::move(response));
                      });
  });
}

void LabArchiveEndpoints::get_runs(const Request& request, Responder respond) {
  std::vector<std::string> filters;
  try {
    filters = parse_lab_run_filters(std::string(request.target()));
  } catch (const std::invalid_argument& e) {
    return respond(error_response(request, http::status::bad_request, e.what()));
  }
  on_pool(request, std::move(respond), [filters](const auto& connection) {
    lab_archive::LabRunReader reader(connection);
    return lab_run_list_json(reader, filters, kPickerRuns);
  });
}

void LabArchiveEndpoints::get_stream(const Request& request, const std::string& run_uuid,
                                     Responder respond) {
  ReplayQuery query;
  try {
    query = parse_replay_query(std::string(request.target()));
  } catch (const std::invalid_argument& e) {
    return respond(error_response(request, http::status::bad_request, e.what()));
  }
  auto model = context_->hub->model();  // drawn over the run as over the live stream
  on_pool(request, std::move(respond), [run_uuid, query, model](const auto& connection) {
    lab_archive::LabRunReader reader(connection);
    return lab_run_stream_json(reader, run_uuid, query, model);
  });
}

}  // namespace rig::api
