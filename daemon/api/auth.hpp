#pragma once
// API access: rigd binds to 127.0.0.1 by default; any other bind requires a token read
// from a file only the service user can read. With a token configured, every request but
// the static page and stop/e-stop (always allowed: they make the rig safe) must carry it,
// as "Authorization: Bearer TOKEN" or, for WebSocket upgrades, "?token=TOKEN".
#include <optional>
#include <string>

#include "http_types.hpp"

namespace rig::api {

// Reads and checks the token file (mode 0600 or stricter, non-empty); throws naming the file.
std::string load_token(const std::string& path);

class ApiAuth {
 public:
  explicit ApiAuth(std::optional<std::string> token) : token_(std::move(token)) {}
  bool required() const { return token_.has_value(); }
  bool authorized(const Request& request) const;

 private:
  std::optional<std::string> token_;
};

}  // namespace rig::api
