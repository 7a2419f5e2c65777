#pragma once
// Cross-site request defence for the API (CSRF and DNS rebinding). Every other web page the
// technician has open runs in the same browser as the overlay page and can send requests to
// 127.0.0.1:8080; a token does not help on loopback, where there is none by default. So:
//  - Host: a request must name this rigd as an IP literal, "localhost", this machine's host
//    name, or a host of `api.allowed_origins`. A DNS-rebinding page sends its own domain
//    name and is refused, for reads too.
//  - Origin: a browser names the page that sent a request. A state-changing request or a
//    WebSocket upgrade from a page of another origin (or the opaque origin "null") is
//    refused. Clients without an Origin header (the rig CLI, curl) are not browsers.
//  - Content-Type: state-changing requests must be JSON. A foreign page can send a
//    text/plain or form POST without asking; application/json needs a CORS preflight that
//    rigd never grants.
// Stop, e-stop and haptic stop are exempt from all three: making the rig safe is never
// refused, whoever asks (the worst a foreign page can do with them is stop a cut).
#include <optional>
#include <string>
#include <vector>

#include "http_types.hpp"

namespace rig::api {

class RequestGuard {
 public:
  // allowed_origins: comma-separated origins ("https://rig07.lab:8443, http://rig07:8080")
  // whose pages may command this rigd besides its own; their hosts are allowed as Host too.
  RequestGuard(const std::string& allowed_origins, std::string machine_host_name);

  // Why the request is refused, or nothing. state_changing: POST and the like.
  std::optional<std::string> refusal(const Request& request, bool state_changing) const;
  // The same for a WebSocket upgrade (it opens a channel as the page's origin).
  std::optional<std::string> upgrade_refusal(const Request& request) const;

 private:
  bool host_allowed(const std::string& host) const;
  bool origin_allowed(const std::string& origin, const std::string& host_header) const;

  std::vector<std::string> allowed_origins_;  // normalised: lower case, no trailing '/'
  std::vector<std::string> allowed_hosts_;    // lower case, without port
};

// Requests that make the rig safe (stop, e-stop, haptic stop): never refused, for want of a
// token, a same-origin page or a free connection slot.
bool is_safety_request(const Request& request);

// Splits "host:port", "[v6]:port", "host" into the host part (lower case, brackets kept).
std::string host_without_port(const std::string& host_header);

}  // namespace rig::api
