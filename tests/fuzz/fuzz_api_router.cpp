// libFuzzer target: rigd's API router with everything behind it that a request can reach
// (router paths and query strings, the CSRF guard, the token check, the archive endpoints
// on a scratch archive, static files, commands answered by a stand-in for the RT loop).
// The bytes are one HTTP request, parsed with the server's limits.
// A finding is a memory error, UB, an exception out of the router, a 500 (a request the
// router did not judge), a command or archive answer without the token, a state-changing
// success that was not JSON, or a static file from outside the web root.
#include <spdlog/spdlog.h>
#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/beast/http.hpp>

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

#include "api_router.hpp"
#include "fuzz_support.hpp"
#include "stream_hub.hpp"

namespace {

namespace http = boost::beast::http;
using rig::fuzz::kToken;

struct Fixture {
  Fixture() : hub(channels, 20.0, 50) {
    spdlog::set_level(spdlog::level::off);
    std::filesystem::create_directories(dir.path / "web");
    std::ofstream(dir.path / "web" / "index.html") << rig::fuzz::kPage;
    std::ofstream(dir.path / "secret.txt") << "outside the web root";
    config.archive.path = (dir.path / "archive.sqlite").string();
    config.api.web_root = (dir.path / "web").string();
    config.api.allowed_origins = "http://rig07:8080";
    context.channels = &channels;
    context.hub = &hub;
    context.config = &config;
    context.version = "fuzz";
    context.auth = rig::api::ApiAuth(std::string(kToken));
    context.guard = rig::api::RequestGuard(config.api.allowed_origins, "rigbench");
  }

  // The RT loop's part: every queued command is answered, accepted (so the checks below see
  // commands succeed; nothing moves here).
  void answer_commands() {
    rig::rt::Command command;
    while (channels.commands.pop(command)) {
      auto& slot =
          status.recent_answers[status.recent_answer_count++ % status.recent_answers.size()];
      slot.id = command.id;
      slot.result = rig::rt::CommandResult::kAccepted;
    }
    channels.status.publish(status);
  }

  rig::fuzz::ScratchDir dir{"rig-fuzz-router"};
  rig::rt::LoopChannels channels{1024};
  rig::service::StreamHub hub;
  rig::config::RigdConfig config;
  rig::api::ApiContext context;
  rig::rt::StatusSnapshot status{};
};

Fixture& fixture() {
  static Fixture* f = new Fixture;  // never destroyed: the archive thread may outlive exit
  return *f;
}

bool is_static(const rig::api::Request& request) {
  const std::string target(request.target());
  const std::string path = target.substr(0, target.find('?'));
  return request.method() == http::verb::get && path.rfind("/api/", 0) != 0 && path != "/metrics";
}

void check(const rig::api::Request& request, const rig::api::Response& response) {
  const unsigned status = response.result_int();
  if (status == 500) rig::fuzz::fail("500 for a request", response.body());
  if (status >= 300) return;
  const bool safety = rig::api::is_safety_request(request);
  if (std::string(request.target()).rfind("/proto/messages.json", 0) == 0)
    return;  // public, like the page
  if (is_static(request)) {
    if (response.body() != rig::fuzz::kPage)
      rig::fuzz::fail("a static file that is not the page", response.body());
    return;
  }
  if (!safety && !rig::fuzz::carries_token(request))
    rig::fuzz::fail("answered without the token", std::string(request.target()));
  const bool reads = request.method() == http::verb::get || request.method() == http::verb::head;
  if (!safety && !reads && !rig::fuzz::is_json_content_type(request))
    rig::fuzz::fail("a command that was not JSON", std::string(request.target()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Fixture& f = fixture();
  const std::optional<rig::api::Request> request = rig::fuzz::parse_request(data, size);
  if (!request) return 0;
  // POST /api/model loads the file the body names (any file rigd can read): it must refuse
  // what is not a small regular model file (/dev/zero blocked it once) and answer, never 500.
  boost::asio::io_context io;
  auto busy = boost::asio::make_work_guard(io);  // waits for the archive thread's answers
  std::optional<rig::api::Response> response;
  {
    rig::api::ApiRouter router(io, f.context);
    router.handle(*request, [&response](rig::api::Response&& r) { response = std::move(r); });
    for (int i = 0; i < 3000 && !response; ++i) {
      f.answer_commands();
      io.run_one_for(std::chrono::milliseconds(1));
    }
  }  // joins the archive thread; handlers it posted since are dropped with `io`, never run
  if (!response) rig::fuzz::fail("no answer within 3 s", std::string(request->target()));
  check(*request, *response);
  return 0;
}
