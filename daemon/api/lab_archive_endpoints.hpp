#pragma once
// GET /api/lab-archive/runs[?rig=&eye_lot=&since=&key=value] and
// GET /api/lab-archive/runs/{uuid}/stream[?from=&limit=]: the lab's PostgreSQL archive for the
// page's run picker. The queries run on a thread of their own, each on a fresh connection
// (a server far away or down delays only this answer, never Stop on the I/O thread); the
// response goes back to the I/O thread, which alone writes to connections.
#include <boost/asio/io_context.hpp>
#include <boost/asio/thread_pool.hpp>

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "api_context.hpp"
#include "http_types.hpp"

namespace rig::api {

class LabArchiveEndpoints {
 public:
  // Off (503) unless context.lab_archive_connection is set ([lab_archive] enabled).
  LabArchiveEndpoints(boost::asio::io_context& io, ApiContext& context);
  ~LabArchiveEndpoints();

  void get_runs(const Request& request, Responder respond);
  void get_stream(const Request& request, const std::string& run_uuid, Responder respond);

 private:
  using Work = std::function<std::string(
      const std::vector<std::pair<std::string, std::string>>& connection)>;
  // Runs work on the pool; its JSON (or the error, as 400/404/502) is sent from the I/O thread.
  void on_pool(const Request& request, Responder respond, Work work);

  boost::asio::io_context* io_;
  ApiContext* context_;
  boost::asio::thread_pool pool_{1};
};

}  // namespace rig::api
