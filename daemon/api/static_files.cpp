// The overlay page's files, served from web_root.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "api_router.hpp"

namespace rig::api {
namespace {

std::string mime_type(const std::filesystem::path& path) {
  const std::string ext = path.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".svg") return "image/svg+xml";
  if (ext == ".png") return "image/png";
  if (ext == ".ico") return "image/x-icon";
  return "application/octet-stream";
}

}  // namespace

Response serve_static(const Request& request, const std::string& web_root) {
  std::string target(request.target());
  target = target.substr(0, target.find('?'));
  if (target == "/") target = "/index.html";
  // An origin-form target always starts with '/' (RFC 9112 §3.2.1); anything else
  // ("?x", "*", "http://…") names no file of ours.
  if (target.empty() || target.front() != '/' || target.find("..") != std::string::npos ||
      target.find('\0') != std::string::npos) {
    return error_response(request, http::status::bad_request,
                          "invalid path: the request target must start with '/'");
  }
  std::error_code ec;
  const std::filesystem::path root = std::filesystem::weakly_canonical(web_root, ec);
  const std::filesystem::path file = std::filesystem::weakly_canonical(root / target.substr(1), ec);
  const auto [root_end, file_it] =
      std::mismatch(root.begin(), root.end(), file.begin(), file.end());
  if (ec || root_end != root.end() || !std::filesystem::is_regular_file(file)) {
    return error_response(request, http::status::not_found, "no such file: " + target);
  }
  std::ifstream in(file, std::ios::binary);
  std::ostringstream content;
  content << in.rdbuf();
  return make_response(request, http::status::ok, content.str(), mime_type(file));
}

}  // namespace rig::api
