#include "api_router.hpp"

#include <spdlog/spdlog.h>
#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <regex>
#include <sstream>

#include "archive_endpoints.hpp"
#include "haptic_control.hpp"
#include "json_text.hpp"
#include "lab_archive_endpoints.hpp"
#include "lab_service.hpp"
#include "model_lint.hpp"
#include "sqlite_handle.hpp"
#include "status_view.hpp"

namespace rig::api {
namespace {

std::string path_of(const Request& request) {
  const std::string target(request.target());
  return target.substr(0, target.find('?'));
}

bool is_loop_command(const std::string& name, rt::CommandKind& kind) {
  static const std::pair<const char*, rt::CommandKind> kCommands[] = {
      {"home", rt::CommandKind::kHome},   {"tare", rt::CommandKind::kTare},
      {"stop", rt::CommandKind::kStop},   {"estop", rt::CommandKind::kEStop},
      {"reset", rt::CommandKind::kReset}, {"start", rt::CommandKind::kStart}};
  for (const auto& [n, k] : kCommands) {
    if (name == n) {
      kind = k;
      return true;
    }
  }
  return false;
}

nlohmann::json parse_body(const Request& request) {
  if (request.body().empty()) return nlohmann::json::object();
  return nlohmann::json::parse(request.body());  // throws on bad JSON
}

}  // namespace

Response make_response(const Request& request, http::status status, std::string body,
                       const std::string& content_type) {
  Response response{status, request.version()};
  response.set(http::field::server, "rigd");
  response.set(http::field::content_type, content_type);
  response.set(http::field::cache_control, "no-store");
  response.keep_alive(request.keep_alive());
  response.body() = std::move(body);
  response.prepare_payload();
  return response;
}

Response error_response(const Request& request, http::status status, const std::string& error,
                        const std::string& field) {
  proto::ErrorReply reply;
  reply.error = error;
  if (!field.empty()) reply.field = field;
  // The error may quote what the client sent (a Host, a path, a JSON parser's view of the
  // body): bytes that are not UTF-8 are replaced, not thrown about (fuzz_api_router).
  return make_response(request, status, json_text(nlohmann::json(reply)));
}

ApiRouter::ApiRouter(boost::asio::io_context& io, ApiContext& context)
    : io_(&io),
      context_(&context),
      archive_(std::make_unique<ArchiveEndpoints>(io, context)),
      lab_archive_(std::make_unique<LabArchiveEndpoints>(io, context)) {}

ApiRouter::~ApiRouter() = default;

// The endpoint for an allowed request; what it throws, handle() answers.
void ApiRouter::route(const Request& request, const std::string& path, bool static_file,
                      const Responder& respond) {
  const bool get = request.method() == http::verb::get;
  const bool post = request.method() == http::verb::post;
  rt::CommandKind kind{};
  // At most 18 digits: any such id fits std::stoll (a longer one was a 500, fuzz_api_router).
  static const std::regex kRunPath(
      R"(^/api/runs/(\d{1,18})(/csv|/samples|/stream|/frames/\d{1,9})?$)");
  std::smatch m;
  if (get && path == "/api/status")
    return respond(make_response(request, http::status::ok, status_json(*context_)));
  if (get && path == "/metrics")
    return respond(make_response(request, http::status::ok, prometheus_metrics(*context_),
                                 "text/plain; version=0.0.4"));
  if (get && path == "/api/runs") return archive_->get_runs(request, respond);
  if (get && std::regex_match(path, m, kRunPath))
    return archive_->get_run(request, std::stoll(m[1].str()), m[2].str(), respond);
  static const std::regex kLabRunPath(R"(^/api/lab-archive/runs/([^/]{1,64})/stream$)");
  if (get && path == "/api/lab-archive/runs") return lab_archive_->get_runs(request, respond);
  if (get && std::regex_match(path, m, kLabRunPath))
    return lab_archive_->get_stream(request, m[1].str(), respond);
  if (path == "/api/model" && (get || post)) return model(request, respond);
  if (post && path.rfind("/api/lab/", 0) == 0) return lab(request, path.substr(9), respond);
  if ((get || post) && (path == "/api/haptic" || path == "/api/haptic/stop"))
    return haptic(request, path, respond);
  if (post && (path == "/api/run" || path == "/api/arm"))
    return post_run(request, path == "/api/run", respond);
  if (post && path.rfind("/api/", 0) == 0 && is_loop_command(path.substr(5), kind))
    return post_command(request, kind, respond);
  if (get && path == "/proto/messages.json")
    return respond(make_response(request, http::status::ok, proto::messages_schema_json()));
  if (static_file) return respond(serve_static(request, context_->config->api.web_root));
  return respond(
      error_response(request, http::status::not_found,
                     "no such endpoint: " + std::string(request.method_string()) + " " + path));
}

void ApiRouter::handle(const Request& request, const Responder& respond) {
  context_->counters.http_requests.fetch_add(1);
  const std::string path = path_of(request);
  const bool get = request.method() == http::verb::get;
  // Stopping is never refused: not for want of a token either.
  const bool safe_command = is_safety_request(request);  // request_guard.hpp
  const bool static_file = get && path.rfind("/api/", 0) != 0 && path != "/metrics";
  if (!safe_command) {
    if (const auto why =
            context_->guard.refusal(request, !get && request.method() != http::verb::head)) {
      context_->counters.refused_cross_site.fetch_add(1);
      spdlog::warn("api: refused {} {}: {}", std::string(request.method_string()), path, *why);
      return respond(error_response(request, http::status::forbidden, *why));
    }
  }
  if (!static_file && !safe_command && !context_->auth.authorized(request)) {
    context_->counters.refused_unauthorized.fetch_add(1);
    spdlog::warn("api: refused {} {} without a valid token", std::string(request.method_string()),
                 path);
    return respond(
        error_response(request, http::status::unauthorized, "a valid API token is required"));
  }
  try {
    route(request, path, static_file, respond);
  } catch (const proto::ProtoError& e) {
    context_->counters.refused_invalid.fetch_add(1);
    return respond(error_response(request, http::status::bad_request, e.what(), e.field()));
  } catch (const nlohmann::json::exception& e) {
    context_->counters.refused_invalid.fetch_add(1);
    return respond(error_response(request, http::status::bad_request,
                                  std::string("request body is not valid JSON: ") + e.what()));
  } catch (const archive::ArchiveError& e) {  // disk full, I/O error: say so, do not start anything
    spdlog::error("api: {} {}: archive: {}", std::string(request.method_string()), path, e.what());
    return respond(error_response(request, http::status::insufficient_storage,
                                  std::string("archive cannot be written: ") + e.what()));
  } catch (const std::exception& e) {
    spdlog::error("api: {} {}: {}", std::string(request.method_string()), path, e.what());
    return respond(error_response(request, http::status::internal_server_error, e.what()));
  }
}

namespace {

// Waits for the RT loop's answer to one command without blocking the I/O thread: polls
// the status every millisecond on a timer, for at most two seconds.
class CommandWait : public std::enable_shared_from_this<CommandWait> {
 public:
  CommandWait(boost::asio::io_context& io, ApiContext& context, Request request,
              rt::Command command, Responder respond,
              std::function<void(rt::CommandResult)> on_answer)
      : timer_(io),
        context_(&context),
        request_(std::move(request)),
        command_(command),
        respond_(std::move(respond)),
        on_answer_(std::move(on_answer)),
        deadline_(std::chrono::steady_clock::now() + std::chrono::seconds(2)) {}

  void check() {
    const rt::StatusSnapshot st = context_->channels->status.read();
    if (const auto result = st.answer_to(command_.id)) return answer(st, *result);
    if (std::chrono::steady_clock::now() > deadline_) {
      return respond_(error_response(request_, http::status::gateway_timeout,
                                     "the RT loop did not answer the command"));
    }
    timer_.expires_after(std::chrono::milliseconds(1));
    timer_.async_wait([self = shared_from_this()](const boost::system::error_code& ec) {
      if (!ec) self->check();
    });
  }

 private:
  void answer(const rt::StatusSnapshot& st, rt::CommandResult result) {
    if (on_answer_) on_answer_(result);
    proto::CommandReply reply;
    reply.ok = result == rt::CommandResult::kAccepted;
    reply.command = std::string(rt::to_string(command_.kind));
    reply.result = std::string(rt::to_string(result));
    reply.state = std::string(rt::to_string(st.state));
    if (command_.params.run_id != 0) reply.run_id = command_.params.run_id;
    respond_(make_response(request_, reply.ok ? http::status::ok : http::status::conflict,
                           json_text(nlohmann::json(reply))));
  }

  boost::asio::steady_timer timer_;
  ApiContext* context_;
  Request request_;
  rt::Command command_;
  Responder respond_;
  std::function<void(rt::CommandResult)> on_answer_;
  std::chrono::steady_clock::time_point deadline_;
};

}  // namespace

void ApiRouter::send_command(const Request& request, const rt::Command& command, Responder respond,
                             std::function<void(rt::CommandResult)> on_answer) {
  if (!context_->channels->commands.push(command)) {
    return respond(error_response(request, http::status::service_unavailable,
                                  "command queue full: try again"));
  }
  std::make_shared<CommandWait>(*io_, *context_, request, command, std::move(respond),
                                std::move(on_answer))
      ->check();
}

void ApiRouter::post_command(const Request& request, rt::CommandKind kind, Responder respond) {
  rt::Command command;
  command.kind = kind;
  command.id = next_command_id_++;
  if (kind == rt::CommandKind::kStop || kind == rt::CommandKind::kEStop)
    spdlog::warn("api: {} requested", rt::to_string(kind));
  send_command(request, command, std::move(respond));
}

void ApiRouter::post_run(const Request& request, bool start, const Responder& respond) {
  const proto::RunRequest run = parse_body(request).get<proto::RunRequest>();
  archive::NewRun row;
  row.eye_id = run.eye_id;
  row.iop_mmHg = run.iop_mmHg;
  row.velocity_mm_s = run.velocity_mm_s;
  row.depth_mm = run.depth_mm;
  row.hold_s = run.hold_s.value_or(0.0);
  row.post_mortem_h = run.post_mortem_h;
  row.operator_name = run.operator_.value_or("");
  row.notes = run.notes.value_or("");
  if (run.meta) row.meta.assign(run.meta->begin(), run.meta->end());
  row.config_hash = context_->config->hash;
  row.software_version = context_->version;
  row.surface_mm = context_->config->loop.motion.surface_mm;
  row.rate_hz = context_->config->loop.rate_hz;
  const proto::RunRequest accepted = run;
  archive_->create_run(
      request, std::move(row),
      // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
      [this, request, respond, accepted, start](std::int64_t run_id) {
        rt::Command command;
        command.kind = rt::CommandKind::kArm;
        command.id = next_command_id_++;
        command.params.iop_mmHg = accepted.iop_mmHg;
        command.params.velocity_mm_s = accepted.velocity_mm_s;
        command.params.depth_mm = accepted.depth_mm;
        command.params.hold_s = accepted.hold_s.value_or(0.0);
        command.params.start_when_settled = start && accepted.start.value_or(true);
        command.params.run_id = run_id;
        send_command(request, command, respond, [this, run_id](rt::CommandResult result) {
          if (result != rt::CommandResult::kAccepted)
            archive_->discard_refused_run(run_id, std::string(rt::to_string(result)));
        });
      },
      respond);
}

void ApiRouter::model(const Request& request, const Responder& respond) {
  if (request.method() == http::verb::post) {
    const proto::ModelSelect select = parse_body(request).get<proto::ModelSelect>();
    try {
      auto loaded = std::make_shared<const model::ForceModel>(model::ForceModel::load(select.file));
      // A printed-form file is drawn as printed (never as our reading), and said so.
      if (loaded->form == model::ModelForm::kPrinted)
        spdlog::warn("api: {}", model::printed_form_warning(*loaded));
      context_->hub->set_model(std::move(loaded));
      spdlog::info("api: live model is now {}", select.file);
    } catch (const std::exception& e) {
      return respond(error_response(request, http::status::unprocessable_entity, e.what(), "file"));
    }
  }
  const double iop = context_->channels->status.read().params.iop_mmHg;
  respond(make_response(request, http::status::ok, context_->hub->model_curve_json(iop)));
}

void ApiRouter::lab(const Request& request, const std::string& action, const Responder& respond) {
  if (action != "compare" && action != "diagnose" && action != "fit") {
    return respond(
        error_response(request, http::status::not_found, "no lab action '" + action + "'"));
  }
  if (context_->lab == nullptr)
    return respond(
        error_response(request, http::status::service_unavailable, "the model lab is not running"));
  const proto::LabRequest lab_request = parse_body(request).get<proto::LabRequest>();
  boost::asio::io_context* io = io_;
  // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
  context_->lab->submit(action, lab_request, [io, request, respond](int status, std::string body) {
    // NOLINTNEXTLINE(bugprone-exception-escape): the closure's implicit move (clang-tidy 14)
    boost::asio::post(*io, [request, respond, status, body = std::move(body)]() mutable {
      respond(make_response(request, static_cast<http::status>(status), std::move(body)));
    });
  });
}

}  // namespace rig::api

namespace rig::api {

void ApiRouter::haptic(const Request& request, const std::string& path, Responder respond) {
  HapticControl* control = context_->haptic;
  if (control == nullptr)
    return respond(error_response(request, http::status::service_unavailable,
                                  "haptic playback is not available"));
  const auto reply = [&](http::status status) {
    respond(make_response(request, status, json_text(nlohmann::json(control->status()))));
  };
  if (request.method() == http::verb::get) return reply(http::status::ok);
  if (path == "/api/haptic/stop") {
    control->stop();
    return reply(http::status::ok);
  }
  const proto::HapticRequest haptic_request = parse_body(request).get<proto::HapticRequest>();
  try {
    if (!control->start(haptic_request)) {
      return respond(error_response(request, http::status::conflict,
                                    "a haptic session is running: stop it first"));
    }
  } catch (const std::exception& e) {
    context_->counters.refused_invalid.fetch_add(1);
    return respond(error_response(request, http::status::bad_request, e.what(), "source"));
  }
  reply(http::status::accepted);
}

}  // namespace rig::api
