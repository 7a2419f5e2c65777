#include "auth.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rig::api {
namespace {

bool constant_time_equal(const std::string& a, const std::string& b) {
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  const std::size_t n = std::min(a.size(), b.size());
  for (std::size_t i = 0; i < n; ++i) diff |= static_cast<unsigned char>(a[i] ^ b[i]);
  return diff == 0;
}

// The page URL-encodes the token (a base64 token has '+', '/', '='); '+' stays '+' here
// because encodeURIComponent never produces it for a space.
std::string percent_decoded(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() &&
        std::isxdigit(static_cast<unsigned char>(text[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(text[i + 2]))) {
      out.push_back(static_cast<char>(std::stoi(text.substr(i + 1, 2), nullptr, 16)));
      i += 2;
    } else {
      out.push_back(text[i]);
    }
  }
  return out;
}

std::string query_token(const std::string& target) {
  const auto q = target.find('?');
  if (q == std::string::npos) return {};
  std::istringstream query(target.substr(q + 1));
  std::string pair;
  while (std::getline(query, pair, '&')) {
    if (pair.rfind("token=", 0) == 0) return percent_decoded(pair.substr(6));
  }
  return {};
}

}  // namespace

std::string load_token(const std::string& path) {
  struct stat info {};
  if (stat(path.c_str(), &info) != 0)
    throw std::runtime_error("api.token_file " + path + ": cannot read it");
  if ((info.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    throw std::runtime_error("api.token_file " + path + ": readable by others (chmod 600 it)");
  }
  std::ifstream in(path);
  std::string token;
  std::getline(in, token);
  while (!token.empty() && (token.back() == '\r' || token.back() == ' ')) token.pop_back();
  if (token.size() < 16)
    throw std::runtime_error("api.token_file " + path + ": token shorter than 16 characters");
  return token;
}

bool ApiAuth::authorized(const Request& request) const {
  if (!token_) return true;
  const auto header = request[http::field::authorization];
  const std::string bearer = "Bearer ";
  if (header.size() > bearer.size() && header.substr(0, bearer.size()) == bearer) {
    return constant_time_equal(std::string(header.substr(bearer.size())), *token_);
  }
  const std::string from_query = query_token(std::string(request.target()));
  return !from_query.empty() && constant_time_equal(from_query, *token_);
}

}  // namespace rig::api
