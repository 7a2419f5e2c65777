#pragma once
// Shared by the API fuzz targets: the server's request parser, a scratch directory, the
// token they run with, and the independent checks of what an answered request must carry.
#include <boost/beast/http.hpp>

#include <unistd.h>
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>

namespace rig::fuzz {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;

inline constexpr const char* kToken = "fuzzT0kenOfTheRig+42/x=";  // base64 characters included
inline constexpr const char* kPage = "<!doctype html><title>rig</title>";

// A directory of its own under TMPDIR, removed at exit.
struct ScratchDir {
  explicit ScratchDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::filesystem::path path;
};

[[noreturn]] inline void fail(const char* what, const std::string& detail) {
  std::fprintf(stderr, "FUZZ FINDING: %s: %s\n", what, detail.substr(0, 300).c_str());
  std::abort();
}

// The bytes as rigd's HTTP session reads them (api.max_body_bytes, 16 KiB of header).
inline std::optional<Request> parse_request(const std::uint8_t* data, std::size_t size) {
  http::request_parser<http::string_body> parser;
  parser.eager(true);
  parser.body_limit(64 * 1024);
  parser.header_limit(16 * 1024);
  boost::beast::error_code ec;
  parser.put(boost::asio::buffer(data, size), ec);
  if (ec || !parser.is_done()) return std::nullopt;
  return parser.release();
}

inline std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

inline std::string percent_decoded(const std::string& text) {
  std::string out;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() &&
        std::isxdigit(static_cast<unsigned char>(text[i + 1])) != 0 &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2])) != 0) {
      out.push_back(static_cast<char>(std::strtol(text.substr(i + 1, 2).c_str(), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(text[i]);
    }
  }
  return out;
}

// The token as a bearer header, or anywhere in the (decoded) query string.
inline bool carries_token(const Request& request) {
  if (std::string(request[http::field::authorization]) == std::string("Bearer ") + kToken)
    return true;
  const std::string target(request.target());
  const auto q = target.find('?');
  return q != std::string::npos &&
         percent_decoded(target.substr(q)).find(kToken) != std::string::npos;
}

inline bool is_json_content_type(const Request& request) {
  std::string type = lower(std::string(request[http::field::content_type]));
  type = type.substr(0, type.find(';'));
  type.erase(0, type.find_first_not_of(" \t"));
  type.erase(type.find_last_not_of(" \t") + 1);
  return type == "application/json";
}

}  // namespace rig::fuzz
