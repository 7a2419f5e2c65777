// libFuzzer target: the API's access checks on the headers a client controls - the token
// (Authorization: Bearer, ?token= for WebSocket upgrades), Host (DNS rebinding), Origin and
// Content-Type (cross-site requests). The input is
// "METHOD\nTARGET\nHost\nOrigin\nAuthorization\nContent-Type", a field left out is a header not
// sent. A finding is a memory error, UB, an exception, or a request let through that an independent
// reading of the rules refuses.
#include <arpa/inet.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "auth.hpp"
#include "fuzz_support.hpp"
#include "request_guard.hpp"

namespace {

namespace http = boost::beast::http;
using rig::fuzz::fail;
using rig::fuzz::lower;

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  return first == std::string::npos ? std::string()
                                    : s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

// The host part of a Host header: "[v6]" with brackets, or up to the first ':'.
bool host_is_ours(const std::string& header) {
  const std::string h = lower(trimmed(header));
  std::string host = h.substr(0, h.find(':'));
  if (!h.empty() && h.front() == '[')
    host = h.substr(0, h.find(']') == std::string::npos ? h.size() : h.find(']') + 1);
  for (const char* name : {"localhost", "rigbench", "rigbench.local", "rig07"}) {
    if (host == name) return true;
  }
  unsigned char address[16];
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')
    return inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), address) == 1;
  return inet_pton(AF_INET, host.c_str(), address) == 1;
}

bool origin_is_ours(const std::string& origin_header, const std::string& host_header) {
  std::string origin = lower(trimmed(origin_header));
  while (!origin.empty() && origin.back() == '/') origin.pop_back();
  const std::string host = lower(trimmed(host_header));
  return origin == "http://" + host || origin == "https://" + host || origin == "http://rig07:8080";
}

std::vector<std::string> fields_of(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> fields(1);
  for (std::size_t i = 0; i < size && fields.size() <= 6; ++i) {
    const char c = static_cast<char>(data[i]);
    if (c == '\n') {
      fields.emplace_back();
    } else if (c != '\r' && c != '\0') {
      fields.back().push_back(c);
    }
  }
  if (fields.size() > 6) fields.resize(6);
  return fields;
}

rig::fuzz::Request request_of(const std::vector<std::string>& f) {
  static const http::verb kVerbs[] = {http::verb::get, http::verb::post, http::verb::head,
                                      http::verb::put, http::verb::delete_};
  rig::fuzz::Request request;
  request.method(kVerbs[f[0].size() % 5]);
  request.target(f.size() > 1 && !f[1].empty() ? f[1] : "/");
  const http::field headers[] = {http::field::host, http::field::origin, http::field::authorization,
                                 http::field::content_type};
  for (std::size_t k = 0; k < 4; ++k) {
    if (f.size() > k + 2) request.set(headers[k], f[k + 2]);
  }
  return request;
}

void check_guard(const rig::api::RequestGuard& guard, const rig::fuzz::Request& request) {
  const std::string host(request[http::field::host]);
  const bool has_origin = request.find(http::field::origin) != request.end();
  const std::string origin(request[http::field::origin]);
  if (!guard.refusal(request, false) && !host_is_ours(host))
    fail("a foreign Host let through", host);
  if (!guard.refusal(request, true)) {
    if (!rig::fuzz::is_json_content_type(request))
      fail("a command that is not JSON let through",
           std::string(request[http::field::content_type]));
    if (has_origin && !origin_is_ours(origin, host))
      fail("a command from a foreign page let through", origin);
  }
  if (!guard.upgrade_refusal(request)) {
    if (!host_is_ours(host)) fail("an upgrade with a foreign Host let through", host);
    if (has_origin && !origin_is_ours(origin, host))
      fail("an upgrade from a foreign page let through", origin);
  }
  (void)rig::api::host_without_port(host);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const rig::api::ApiAuth with_token{std::string(rig::fuzz::kToken)};
  static const rig::api::ApiAuth without_token{std::nullopt};
  static const rig::api::RequestGuard guard{"http://rig07:8080", "rigbench"};
  const rig::fuzz::Request request = request_of(fields_of(data, size));
  if (!without_token.authorized(request))
    fail("refused without a token configured", std::string(request.target()));
  if (with_token.authorized(request) && !rig::fuzz::carries_token(request))
    fail("authorized without the token", std::string(request.target()));
  const std::string bearer(request[http::field::authorization]);
  if (bearer == std::string("Bearer ") + rig::fuzz::kToken && !with_token.authorized(request))
    fail("the right bearer token refused", bearer);
  check_guard(guard, request);
  const std::string target(request.target());
  if (rig::api::is_safety_request(request) &&
      (request.method() != http::verb::post || target.rfind("/api/", 0) != 0)) {
    fail("not a stop, yet exempt from every check", target);
  }
  return 0;
}
