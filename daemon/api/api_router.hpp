#pragma once
// Routes HTTP requests to handlers. Handlers that need the RT loop's answer (commands) or
// the lab's worker answer asynchronously through the Responder; archive work runs on its
// own thread (archive_endpoints.hpp): nothing here blocks the I/O thread.
#include <boost/asio/io_context.hpp>

#include <memory>

#include "api_context.hpp"
#include "http_types.hpp"

namespace rig::api {

class ArchiveEndpoints;
class LabArchiveEndpoints;

class ApiRouter {
 public:
  ApiRouter(boost::asio::io_context& io, ApiContext& context);
  ~ApiRouter();
  void handle(const Request& request, const Responder& respond);

 private:
  void route(const Request& request, const std::string& path, bool static_file,
             const Responder& respond);
  void post_command(const Request& request, rt::CommandKind kind, Responder respond);
  void post_run(const Request& request, bool start, const Responder& respond);
  void send_command(const Request& request, const rt::Command& command, Responder respond,
                    std::function<void(rt::CommandResult)> on_answer = {});
  void model(const Request& request, const Responder& respond);
  void lab(const Request& request, const std::string& action, const Responder& respond);
  void haptic(const Request& request, const std::string& path, Responder respond);

  boost::asio::io_context* io_;
  ApiContext* context_;
  std::unique_ptr<ArchiveEndpoints> archive_;  // run lists, exports, run rows: off the I/O thread
  std::unique_ptr<LabArchiveEndpoints>
      lab_archive_;                            // the lab's PostgreSQL runs: off the I/O thread
  std::uint64_t next_command_id_ = 1'000'000;  // distinct from other senders' ids
};

// Static files of the page under web_root; refuses anything outside it.
Response serve_static(const Request& request, const std::string& web_root);

}  // namespace rig::api
