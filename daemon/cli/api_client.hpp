#pragma once
// The rig CLI's client of rigd's HTTP JSON API (loopback by default, token if configured).
#include <stdexcept>
#include <string>

namespace rig::cli {

struct HttpReply {
  int status = 0;
  std::string body;
};

class ApiClientError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ApiClient {
 public:
  // url: http://host:port ; token: empty for none.
  ApiClient(std::string url, std::string token);
  HttpReply get(const std::string& path) const;
  HttpReply post(const std::string& path, const std::string& json_body = "") const;
  const std::string& url() const { return url_; }

 private:
  HttpReply request(bool post, const std::string& path, const std::string& body) const;
  std::string url_;
  std::string host_;
  std::string port_;
  std::string token_;
};

}  // namespace rig::cli
