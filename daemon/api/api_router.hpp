#pragma once
// Routes HTTP requests to handlers. Handlers that need the RT loop's answer (commands) or
// the lab's worker answer asynchronously through the Responder; nothing here blocks the
// I/O thread for longer than an SQLite read.
#include <boost/asio/io_context.hpp>

#include <memory>

#include "api_context.hpp"
#include "archive.hpp"
#include "http_types.hpp"

namespace rig::api {

class ApiRouter {
 public:
  ApiRouter(boost::asio::io_context& io, ApiContext& context);
  void handle(const Request& request, Responder respond);

 private:
  void post_command(const Request& request, rt::CommandKind kind, Responder respond);
  void post_run(const Request& request, bool start, Responder respond);
  void send_command(const Request& request, const rt::Command& command, Responder respond,
                    std::function<void(rt::CommandResult)> on_answer = {});
  void get_runs(const Request& request, Responder respond);
  void get_run(const Request& request, std::int64_t run_id, const std::string& what, Responder respond);
  void model(const Request& request, Responder respond);
  void lab(const Request& request, const std::string& action, Responder respond);
  void haptic(const Request& request, const std::string& path, Responder respond);
  archive::Archive& archive();

  boost::asio::io_context* io_;
  ApiContext* context_;
  std::unique_ptr<archive::Archive> archive_;
  std::uint64_t next_command_id_ = 1'000'000;  // distinct from other senders' ids
};

// Static files of the page under web_root; refuses anything outside it.
Response serve_static(const Request& request, const std::string& web_root);

}  // namespace rig::api
