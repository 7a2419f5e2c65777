#pragma once
// HTTP types shared by the API's sessions and router, and small response builders.
#include <boost/beast/http.hpp>

#include <functional>
#include <string>

namespace rig::api {

namespace http = boost::beast::http;
using Request = http::request<http::string_body>;
using Response = http::response<http::string_body>;
using Responder = std::function<void(Response&&)>;

Response make_response(const Request& request, http::status status, std::string body,
                       const std::string& content_type = "application/json");
// JSON error reply (proto ErrorReply), optionally naming the request field at fault.
Response error_response(const Request& request, http::status status, const std::string& error,
                        const std::string& field = "");

}  // namespace rig::api
