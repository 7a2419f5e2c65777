#include "request_guard.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cctype>
#include <sstream>

namespace rig::api {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::string trimmed(const std::string& s) {
  const auto first = s.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t") - first + 1);
}

bool is_ip_literal(const std::string& host) {
  unsigned char buffer[16];
  if (host.size() > 2 && host.front() == '[' && host.back() == ']') {
    return inet_pton(AF_INET6, host.substr(1, host.size() - 2).c_str(), buffer) == 1;
  }
  return inet_pton(AF_INET, host.c_str(), buffer) == 1;
}

// "http://host:port/" -> "host:port"; empty if it is not an http(s) origin.
std::string origin_authority(const std::string& origin) {
  for (const char* scheme : {"http://", "https://"}) {
    const std::string prefix(scheme);
    if (origin.rfind(prefix, 0) == 0) {
      std::string rest = origin.substr(prefix.size());
      while (!rest.empty() && rest.back() == '/') rest.pop_back();
      return rest;
    }
  }
  return {};
}

}  // namespace

bool is_safety_request(const Request& request) {
  if (request.method() != http::verb::post) return false;
  const std::string target(request.target());
  const std::string path = target.substr(0, target.find('?'));
  return path == "/api/stop" || path == "/api/estop" || path == "/api/haptic/stop";
}

std::string host_without_port(const std::string& host_header) {
  const std::string host = lower(trimmed(host_header));
  if (!host.empty() && host.front() == '[') {
    const auto close = host.find(']');
    return close == std::string::npos ? host : host.substr(0, close + 1);
  }
  return host.substr(0, host.find(':'));
}

RequestGuard::RequestGuard(const std::string& allowed_origins, std::string machine_host_name) {
  allowed_hosts_ = {"localhost"};
  if (!machine_host_name.empty()) {
    const std::string name = lower(std::move(machine_host_name));
    allowed_hosts_.push_back(name);
    allowed_hosts_.push_back(name + ".local");
  }
  std::istringstream list(allowed_origins);
  std::string item;
  while (std::getline(list, item, ',')) {
    std::string origin = lower(trimmed(item));
    while (!origin.empty() && origin.back() == '/') origin.pop_back();
    const std::string authority = origin_authority(origin);
    if (authority.empty()) continue;  // rejected by the config reader already
    allowed_origins_.push_back(origin);
    allowed_hosts_.push_back(host_without_port(authority));
  }
}

bool RequestGuard::host_allowed(const std::string& host) const {
  if (host.empty()) return false;
  if (is_ip_literal(host)) return true;  // a rebinding page cannot make the browser send one
  return std::find(allowed_hosts_.begin(), allowed_hosts_.end(), host) != allowed_hosts_.end();
}

bool RequestGuard::origin_allowed(const std::string& origin_header,
                                  const std::string& host_header) const {
  std::string origin = lower(trimmed(origin_header));
  while (!origin.empty() && origin.back() == '/') origin.pop_back();
  const std::string authority = origin_authority(origin);
  if (authority.empty()) return false;  // "null", file://, extensions: not a page of ours
  if (authority == lower(trimmed(host_header))) return true;  // same origin as the request's Host
  return std::find(allowed_origins_.begin(), allowed_origins_.end(), origin) !=
         allowed_origins_.end();
}

std::optional<std::string> RequestGuard::refusal(const Request& request,
                                                 bool state_changing) const {
  const std::string host_header(request[http::field::host]);
  if (!host_allowed(host_without_port(host_header))) {
    return "Host '" + host_header + "' is not this rigd (add its origin to api.allowed_origins)";
  }
  if (!state_changing) return std::nullopt;
  if (request.find(http::field::origin) != request.end()) {
    const std::string origin(request[http::field::origin]);
    if (!origin_allowed(origin, host_header)) {
      return "requests from the page at Origin '" + origin + "' may not command this rigd";
    }
  }
  const std::string type = lower(std::string(request[http::field::content_type]));
  if (trimmed(type.substr(0, type.find(';'))) != "application/json") {
    return "a command must be sent as Content-Type: application/json";
  }
  return std::nullopt;
}

std::optional<std::string> RequestGuard::upgrade_refusal(const Request& request) const {
  if (auto why = refusal(request, false)) return why;
  if (request.find(http::field::origin) == request.end()) return std::nullopt;
  const std::string origin(request[http::field::origin]);
  if (!origin_allowed(origin, std::string(request[http::field::host]))) {
    return "WebSocket from the page at Origin '" + origin + "' refused";
  }
  return std::nullopt;
}

}  // namespace rig::api
