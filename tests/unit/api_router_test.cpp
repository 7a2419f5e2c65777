// The API router in-process (no sockets): requests whose path or query a client chose
// freely are judged (4xx), never answered with a 500. Regressions found by fuzz_api_router.
#include <gtest/gtest.h>
#include <spdlog/spdlog.h>
#include <nlohmann/json.hpp>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>

#include <optional>

#include "api_router.hpp"
#include "archive.hpp"
#include "stream_hub.hpp"
#include "test_paths.hpp"

namespace rig::api {
namespace {

class ApiRouterTest : public ::testing::Test {
 protected:
  void SetUp() override {
    spdlog::set_level(spdlog::level::off);
    config_.archive.path = dir_.file("archive.sqlite");
    config_.api.web_root = dir_.path().string();
    context_.channels = &channels_;
    context_.hub = &hub_;
    context_.config = &config_;
  }
  void TearDown() override { spdlog::set_level(spdlog::level::info); }

  Response get(const std::string& target, const std::string& host = "127.0.0.1:8080") {
    Request request{http::verb::get, target, 11};
    request.set(http::field::host, host);
    boost::asio::io_context io;
    auto busy = boost::asio::make_work_guard(io);  // waits for the archive thread's answer
    std::optional<Response> response;
    {
      ApiRouter router(io, context_);
      router.handle(request, [&response](Response&& r) { response = std::move(r); });
      for (int i = 0; i < 2000 && !response; ++i) io.run_one_for(std::chrono::milliseconds(1));
    }
    EXPECT_TRUE(response) << target << ": no answer";
    return response ? *response : Response{};
  }

  testing::ScratchDir dir_{"api-router"};
  rt::LoopChannels channels_{1024};
  service::StreamHub hub_{channels_, 20.0, 50};
  config::RigdConfig config_;
  ApiContext context_;
};

TEST_F(ApiRouterTest, ARunIdTooLargeForAnIntegerIsNoSuchEndpointNotAServerError) {
  for (const char* target : {"/api/runs/99999999999999999999", "/api/runs/9223372036854775808/csv",
                             "/api/runs/00000000000000000000000000001/samples"}) {
    const Response r = get(target);
    EXPECT_EQ(r.result(), http::status::not_found) << target << ": " << r.body();
  }
}

TEST_F(ApiRouterTest, ARunThatDoesNotExistIsNotFound) {
  const Response r = get("/api/runs/123456789012345678");
  EXPECT_EQ(r.result(), http::status::not_found) << r.body();
  EXPECT_NE(r.body().find("no run 123456789012345678"), std::string::npos) << r.body();
}

// Found by fuzz_api_router: a refusal quoting a Host or path that is not UTF-8 threw out of
// the router (nlohmann's dump), so the client got no answer and the I/O thread an exception.
TEST_F(ApiRouterTest, ARefusalQuotingBytesThatAreNotUtf8IsAnsweredAsValidJson) {
  const Response host = get("/api/status", "rig\xff\xfe:8080");
  EXPECT_EQ(host.result(), http::status::forbidden);
  EXPECT_TRUE(nlohmann::json::accept(host.body())) << host.body();
  EXPECT_NE(host.body().find("is not this rigd"), std::string::npos) << host.body();
  const Response path = get("/api/\xc3\x28nothing");
  EXPECT_EQ(path.result(), http::status::not_found);
  EXPECT_TRUE(nlohmann::json::accept(path.body())) << path.body();
}

// Found while fuzzing (issue 14): a run imported from someone's CSV can carry bytes that are
// not UTF-8 in its eye id or notes; listing or opening it answered a 500.
TEST_F(ApiRouterTest, ARunWhoseTextIsNotUtf8IsListedAndOpenedAsValidJson) {
  std::int64_t run_id = 0;
  {
    archive::Archive archive(config_.archive.path);
    run_id = archive.create_run(archive::NewRun{"EYE\xff\xfe-7"});
  }
  for (const std::string& target :
       {std::string("/api/runs"), "/api/runs/" + std::to_string(run_id)}) {
    const Response r = get(target);
    EXPECT_EQ(r.result(), http::status::ok) << target << ": " << r.body();
    EXPECT_TRUE(nlohmann::json::accept(r.body())) << target << ": " << r.body();
    EXPECT_NE(r.body().find("EYE\xef\xbf\xbd"), std::string::npos)
        << target << ": " << r.body();  // U+FFFD
  }
}

// Found by fuzz_api_router in CI: a target that does not start with '/' ("?!pi/runs") reached
// the static-file server, whose substr(1) threw on the empty path: a 500 for a client's typo.
TEST_F(ApiRouterTest, ATargetThatDoesNotStartWithASlashIsABadRequestNamingWhy) {
  for (const char* target : {"?!pi/runs", "?", "*", "index.html", "http://rig/index.html"}) {
    const Response r = get(target);
    EXPECT_EQ(r.result(), http::status::bad_request) << target << ": " << r.body();
    EXPECT_NE(r.body().find("must start with '/'"), std::string::npos)
        << target << ": " << r.body();
  }
}

}  // namespace
}  // namespace rig::api
