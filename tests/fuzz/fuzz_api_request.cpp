// libFuzzer target: what rigd does with the bytes of an API request before any handler
// runs: Beast's HTTP parser with the server's limits, then the JSON body and the generated
// RunRequest validation. Refusals are exceptions or parser errors; anything else is a bug.
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>

#include "rig/proto/messages.hpp"

namespace http = boost::beast::http;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  http::request_parser<http::string_body> parser;
  parser.eager(true);
  parser.body_limit(64 * 1024);  // api.max_body_bytes default
  parser.header_limit(16 * 1024);
  boost::beast::error_code ec;
  parser.put(boost::asio::buffer(data, size), ec);
  if (ec || !parser.is_done()) return 0;
  const auto& request = parser.get();
  (void)request.target();
  try {
    const nlohmann::json body = nlohmann::json::parse(request.body());
    (void)body.get<rig::proto::RunRequest>();
  } catch (const nlohmann::json::exception&) {
  } catch (const rig::proto::ProtoError&) {
  }
  return 0;
}
