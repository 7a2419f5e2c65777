// libFuzzer target: what rigd does with the bytes of an API request before any handler
// runs: Beast's HTTP parser with the server's limits, then the JSON body and the generated
// validation of every request body the API takes (run, model, lab, haptic), up to the
// server's 64 KiB body limit. Refusals are exceptions or parser errors; anything else is a bug.
#include <boost/beast/http.hpp>
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>

#include "rig/proto/messages.hpp"

namespace http = boost::beast::http;

namespace {

// Each decoder on its own: one refusing must not hide another's crash.
template <typename Message>
void decode(const nlohmann::json& body) {
  try {
    const Message message = body.get<Message>();
    (void)nlohmann::json(message).dump(-1, ' ', false,
                                       nlohmann::json::error_handler_t::replace);  // and back
  } catch (const nlohmann::json::exception&) {
  } catch (const rig::proto::ProtoError&) {
  }
}

void decode_as_each_body(const nlohmann::json& body) {
  decode<rig::proto::RunRequest>(body);
  decode<rig::proto::ModelSelect>(body);
  decode<rig::proto::LabRequest>(body);
  decode<rig::proto::HapticRequest>(body);
}

}  // namespace

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
    decode_as_each_body(body);
  } catch (const nlohmann::json::exception&) {
  }
  return 0;
}
